//! The trimmed region meshed (paper 002, section 3.3): inside the trim loop in `(u, v)`,
//! interior points on an equilateral lattice at the element size, kept clear of the
//! loop, joined with the loop's own points by a constrained Delaunay triangulation
//! (`spade`) with the loop's segments as constraints; the triangles outside the loop
//! dropped. The loop's points are the hole's own nodes, so the patch meets the mesh
//! edge for edge: no node is added on the loop and no T-junction is made.

use glam::DVec2;
use spade::{ConstrainedDelaunayTriangulation, Point2, Triangulation};

/// An interior point nearer a loop segment than this share of the element size is
/// dropped: it would make a sliver against the loop.
const CLEARANCE: f64 = 0.55;

/// A trimmed region's triangles: the first `boundary` points are the loop's (in its
/// order), the rest interior lattice points; triangles counter-clockwise in `(u, v)`.
#[derive(Debug, Clone, PartialEq)]
pub struct RegionMesh {
    /// Every point, the loop's first.
    pub uv: Vec<DVec2>,
    /// How many of `uv` are the loop's.
    pub boundary: usize,
    /// The triangles, as indices into `uv`.
    pub triangles: Vec<[usize; 3]>,
}

/// Why a region could not be meshed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum RegionError {
    /// The trim loop crosses or touches itself in `(u, v)`.
    #[error("the loop crosses itself on its base surface")]
    SelfCrossing,
    /// The triangulation failed otherwise.
    #[error("the hole's region could not be triangulated: {0}")]
    Triangulation(String),
}

/// The distance from `q` to the segment `a`-`b`.
fn to_segment(q: DVec2, a: DVec2, b: DVec2) -> f64 {
    let ab = b - a;
    let t = ((q - a).dot(ab) / ab.length_squared().max(f64::MIN_POSITIVE)).clamp(0.0, 1.0);
    q.distance(a + t * ab)
}

/// The points of an equilateral lattice `size` apart inside `loop_uv` and clear of it.
///
/// Row by row: a point is inside where an odd number of the loop's crossings of its row
/// lie to its left (the loop is simple; a loop that crosses itself is refused when it
/// is triangulated), and clear where every loop segment that comes within the
/// clearance of the row lies at least that far from it.
pub fn lattice_inside(loop_uv: &[DVec2], size: f64) -> Vec<DVec2> {
    let n = loop_uv.len();
    let (lo, hi) = loop_uv
        .iter()
        .fold((DVec2::INFINITY, DVec2::NEG_INFINITY), |(lo, hi), &q| {
            (lo.min(q), hi.max(q))
        });
    let row = size * 3f64.sqrt() / 2.0;
    let rows = ((hi.y - lo.y) / row).floor() as usize;
    let clearance = CLEARANCE * size;
    let segment = |k: usize| (loop_uv[k], loop_uv[(k + 1) % n]);
    let mut out = Vec::new();
    let (mut crossings, mut near) = (Vec::new(), Vec::new());
    for r in 1..=rows {
        let y = lo.y + r as f64 * row;
        crossings.clear();
        near.clear();
        for k in 0..n {
            let (a, b) = segment(k);
            // Each segment crosses the row where its ends lie either side, an end on
            // the row counted with the side above (as the winding number counts it).
            if (a.y <= y) != (b.y <= y) {
                crossings.push(a.x + (y - a.y) / (b.y - a.y) * (b.x - a.x));
            }
            if a.y.min(b.y) <= y + clearance && a.y.max(b.y) >= y - clearance {
                near.push(k);
            }
        }
        let shift = if r % 2 == 0 { 0.0 } else { 0.5 * size };
        let mut x = lo.x + shift;
        while x < hi.x {
            let q = DVec2::new(x, y);
            x += size;
            let left = crossings.iter().filter(|&&c| c < q.x).count();
            if left % 2 == 0 {
                continue;
            }
            let clear = near.iter().all(|&k| {
                let (a, b) = segment(k);
                to_segment(q, a, b) >= clearance
            });
            if clear {
                out.push(q);
            }
        }
    }
    out
}

/// Meshes the region inside the closed loop `loop_uv` (no point repeated) with
/// elements about `size` across.
pub fn mesh_region(loop_uv: &[DVec2], size: f64) -> Result<RegionMesh, RegionError> {
    let n = loop_uv.len();
    let mut uv = loop_uv.to_vec();
    uv.extend(lattice_inside(loop_uv, size));
    let edges: Vec<[usize; 2]> = (0..n).map(|i| [i, (i + 1) % n]).collect();
    let points: Vec<Point2<f64>> = uv.iter().map(|q| Point2::new(q.x, q.y)).collect();
    let mut conflicts = 0usize;
    let cdt: ConstrainedDelaunayTriangulation<Point2<f64>> =
        ConstrainedDelaunayTriangulation::try_bulk_load_cdt(points, edges, |_| conflicts += 1)
            .map_err(|e| RegionError::Triangulation(format!("{e:?}")))?;
    if conflicts > 0 || cdt.num_vertices() != uv.len() {
        return Err(RegionError::SelfCrossing);
    }
    // Outside the loop: the faces reached from the hull without crossing one of its
    // segments (a flood on the triangulation's own topology, exact where the loop runs
    // straight and a middle-point test would read rounding).
    let mut outside = vec![false; cdt.num_all_faces()];
    let mut queue = Vec::new();
    for f in cdt.inner_faces() {
        let on_hull = f
            .adjacent_edges()
            .iter()
            .any(|e| !e.is_constraint_edge() && e.rev().face().is_outer());
        if on_hull {
            outside[f.fix().index()] = true;
            queue.push(f);
        }
    }
    while let Some(f) = queue.pop() {
        for e in f.adjacent_edges() {
            if e.is_constraint_edge() {
                continue;
            }
            if let Some(g) = e.rev().face().as_inner() {
                if !outside[g.fix().index()] {
                    outside[g.fix().index()] = true;
                    queue.push(g);
                }
            }
        }
    }
    let mut triangles: Vec<[usize; 3]> = cdt
        .inner_faces()
        .filter(|f| !outside[f.fix().index()])
        .map(|f| f.vertices().map(|v| v.fix().index()))
        .collect();
    flip_slivers(&uv, n, &mut triangles);
    Ok(RegionMesh {
        uv,
        boundary: n,
        triangles,
    })
}

/// Loop points in a line (a straight run of the hole's edge) make, but for rounding, a
/// fan of slivers of no area between them; each sliver is flipped with the triangle
/// across its long side, so its middle point joins that triangle's far point. A sliver
/// whose neighbour is another sliver of the same run waits until that one has been
/// flipped: passes repeat until none is left (or none can go).
fn flip_slivers(uv: &[DVec2], n: usize, triangles: &mut [[usize; 3]]) {
    for _ in 0..n {
        if flip_pass(uv, n, triangles) == 0 {
            break;
        }
    }
}

/// One pass of [`flip_slivers`]: how many slivers it flipped.
fn flip_pass(uv: &[DVec2], n: usize, triangles: &mut [[usize; 3]]) -> usize {
    let area = |t: &[usize; 3]| 0.5 * (uv[t[1]] - uv[t[0]]).perp_dot(uv[t[2]] - uv[t[0]]);
    let mut flipped = 0;
    for k in 0..triangles.len() {
        let t = triangles[k];
        if t.iter().any(|&i| i >= n) {
            continue;
        }
        let longest = (0..3)
            .map(|e| uv[t[e]].distance_squared(uv[t[(e + 1) % 3]]))
            .fold(0.0, f64::max);
        if area(&t).abs() > 1e-9 * longest {
            continue;
        }
        // The sliver's long side runs from a to c past the middle point b.
        for e in 0..3 {
            let (a, b, c) = (t[e], t[(e + 1) % 3], t[(e + 2) % 3]);
            let ac = uv[c] - uv[a];
            let along = (uv[b] - uv[a]).dot(ac) / ac.length_squared().max(f64::MIN_POSITIVE);
            if !(0.0..=1.0).contains(&along) {
                continue;
            }
            // The sliver runs its long side c to a; the triangle across runs it a to c.
            let Some(j) = (0..triangles.len()).find(|&j| {
                j != k && (0..3).any(|f| triangles[j][f] == a && triangles[j][(f + 1) % 3] == c)
            }) else {
                continue;
            };
            let Some(&d) = triangles[j].iter().find(|&&v| v != a && v != c) else {
                continue;
            };
            let (first, second) = ([a, b, d], [b, c, d]);
            let longest_of = |t: &[usize; 3]| {
                (0..3)
                    .map(|e| uv[t[e]].distance_squared(uv[t[(e + 1) % 3]]))
                    .fold(0.0, f64::max)
            };
            if area(&first) > 1e-9 * longest_of(&first)
                && area(&second) > 1e-9 * longest_of(&second)
            {
                triangles[k] = first;
                triangles[j] = second;
                flipped += 1;
            }
            break;
        }
    }
    flipped
}
