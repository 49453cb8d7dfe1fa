//! A region's loops checked and oriented, and nodes placed along them at the element
//! size (paper 004, section 4: boundary nodes by count), every corner kept as a node
//! and an even count on every loop, so the region can be all quads.

use glam::DVec2;

use super::sizing::{chord_for_sag, Sizes};
use super::{QuadError, Region};
use crate::geom::trimmed::{polygon_area, winding};

/// Where the segments `a b` and `c d` meet (touching counts), if they do.
pub fn segments_meet(a: DVec2, b: DVec2, c: DVec2, d: DVec2) -> Option<DVec2> {
    let r = b - a;
    let s = d - c;
    let denom = r.perp_dot(s);
    let scale = (r.length() * s.length()).max(f64::MIN_POSITIVE);
    if denom.abs() <= 1e-12 * scale {
        // Parallel: they meet only if collinear and overlapping.
        if (c - a).perp_dot(r).abs() > 1e-12 * scale {
            return None;
        }
        let rr = r.length_squared().max(f64::MIN_POSITIVE);
        let (t0, t1) = ((c - a).dot(r) / rr, (d - a).dot(r) / rr);
        let (lo, hi) = (t0.min(t1), t0.max(t1));
        return (hi >= 0.0 && lo <= 1.0).then(|| a + r * lo.clamp(0.0, 1.0));
    }
    let t = (c - a).perp_dot(s) / denom;
    let u = (c - a).perp_dot(r) / denom;
    let eps = 1e-12;
    ((-eps..=1.0 + eps).contains(&t) && (-eps..=1.0 + eps).contains(&u)).then(|| a + r * t)
}

/// The region's loops cleaned and checked: repeated points dropped, every point
/// finite, every loop enclosing area, no two edges crossing or touching, every hole
/// inside the outer loop; the outer loop counter-clockwise and the holes clockwise
/// (the region always on the left).
pub fn checked_loops(region: &Region) -> Result<Vec<Vec<DVec2>>, QuadError> {
    let mut loops = Vec::new();
    for (k, raw) in std::iter::once(&region.outer)
        .chain(&region.holes)
        .enumerate()
    {
        if raw.iter().any(|p| !p.is_finite()) {
            return Err(QuadError::NotFinite { loop_index: k });
        }
        let mut l: Vec<DVec2> = Vec::with_capacity(raw.len());
        for &p in raw {
            if l.last().is_none_or(|q: &DVec2| q.distance(p) > 1e-9) {
                l.push(p);
            }
        }
        while l.len() > 1 && l[0].distance(l[l.len() - 1]) <= 1e-9 {
            l.pop();
        }
        let area = polygon_area(l.iter().copied());
        let span = l
            .iter()
            .fold(0.0f64, |m, p| m.max(p.distance(l[0])))
            .max(f64::MIN_POSITIVE);
        if l.len() < 3 || area.abs() <= 1e-12 * span * span {
            return Err(QuadError::Degenerate { loop_index: k });
        }
        if (k == 0) != (area > 0.0) {
            l.reverse();
        }
        loops.push(l);
    }
    check_crossings(&loops)?;
    for (k, hole) in loops.iter().enumerate().skip(1) {
        if winding(loops[0].iter().copied(), hole[0]) == 0 {
            return Err(QuadError::Outside { loop_index: k });
        }
    }
    Ok(loops)
}

/// Every pair of loop edges that cross or touch (other than neighbours on one loop at
/// their shared point), found by a sweep along x.
fn check_crossings(loops: &[Vec<DVec2>]) -> Result<(), QuadError> {
    // (loop, index of the edge's first point, x range)
    let mut edges: Vec<(usize, usize, f64, f64)> = Vec::new();
    for (k, l) in loops.iter().enumerate() {
        for i in 0..l.len() {
            let (a, b) = (l[i], l[(i + 1) % l.len()]);
            edges.push((k, i, a.x.min(b.x), a.x.max(b.x)));
        }
    }
    edges.sort_by(|p, q| p.2.total_cmp(&q.2));
    let point = |k: usize, i: usize| loops[k][i % loops[k].len()];
    for (e, &(k, i, _, hi)) in edges.iter().enumerate() {
        for &(m, j, lo, _) in &edges[e + 1..] {
            if lo > hi {
                break;
            }
            let n = loops[k].len();
            if k == m && (j == (i + 1) % n || i == (j + 1) % n) {
                // Neighbours meet at their shared point; they cross only if they fold
                // back along each other.
                let (shared, p, q) = if j == (i + 1) % n {
                    (point(k, j), point(k, i), point(k, j + 1))
                } else {
                    (point(k, i), point(k, j), point(k, i + 1))
                };
                let (u, v) = (p - shared, q - shared);
                if u.perp_dot(v).abs() <= 1e-12 * u.length() * v.length() && u.dot(v) > 0.0 {
                    return Err(QuadError::Crossing {
                        first: k,
                        second: m,
                        at: shared,
                    });
                }
                continue;
            }
            if let Some(at) =
                segments_meet(point(k, i), point(k, i + 1), point(m, j), point(m, j + 1))
            {
                return Err(QuadError::Crossing {
                    first: k.min(m),
                    second: k.max(m),
                    at,
                });
            }
        }
    }
    Ok(())
}

/// The indices of `points` (a closed loop) where it turns by more than `corner_angle`;
/// none on a smooth loop.
pub fn corners(points: &[DVec2], corner_angle: f64) -> Vec<usize> {
    let n = points.len();
    (0..n)
        .filter(|&i| {
            let a = points[i] - points[(i + n - 1) % n];
            let b = points[(i + 1) % n] - points[i];
            a.angle_to(b).abs() > corner_angle
        })
        .collect()
}

/// The spacing each segment of a side (a polyline) allows: the size wanted there, less where the
/// side curves so tightly that a chord of `size` would sag more than `tolerance` off
/// it. The radius at a point is read from its turn over the segments round it; a chord
/// of length `c` on radius `r` sags `tolerance` when `c = 2 sqrt(2 r t - t^2)`.
pub fn allowed_spacing(side: &[DVec2], sizes: Sizes, tolerance: f64) -> Vec<f64> {
    let at_point = |i: usize| -> f64 {
        let size = sizes.at(side[i]);
        if i == 0 || i + 1 >= side.len() || tolerance.is_nan() || tolerance <= 0.0 {
            return size;
        }
        let (a, b) = (side[i] - side[i - 1], side[i + 1] - side[i]);
        let turn = a.angle_to(b).abs();
        if turn <= 1e-9 {
            return size;
        }
        let r = 0.5 * (a.length() + b.length()) / turn;
        size.min(chord_for_sag(r, tolerance))
    };
    let points: Vec<f64> = (0..side.len()).map(at_point).collect();
    points.windows(2).map(|w| w[0].min(w[1])).collect()
}

/// Nodes along the closed loop `points`, about the wanted size apart (closer where the loop
/// curves, so no piece's chord sags more than `chord_tolerance` off it): every corner (a turn of
/// more than `corner_angle`) is a node, each side between corners divided evenly by
/// arc length into as many pieces as its length over `size` (at least one), and the
/// total made even (one more piece on the side whose pieces are longest) and at least
/// four. A smooth loop is one side from its first point.
pub fn place_nodes(
    points: &[DVec2],
    sizes: Sizes,
    corner_angle: f64,
    chord_tolerance: f64,
) -> Vec<DVec2> {
    let n = points.len();
    let mut starts = corners(points, corner_angle);
    if starts.is_empty() {
        starts.push(0);
    }
    // Each side: the polyline from one corner to the next.
    let sides: Vec<Vec<DVec2>> = (0..starts.len())
        .map(|s| {
            let from = starts[s];
            let to = starts[(s + 1) % starts.len()];
            let len = if to > from { to - from } else { to + n - from };
            (0..=len).map(|k| points[(from + k) % n]).collect()
        })
        .collect();
    let lengths: Vec<f64> = sides
        .iter()
        .map(|s| s.windows(2).map(|w| w[0].distance(w[1])).sum())
        .collect();
    // Each segment's share of pieces: its length over the spacing it allows, so a
    // side's pieces crowd where it curves.
    let measures: Vec<Vec<f64>> = sides
        .iter()
        .map(|side| {
            let spacing = allowed_spacing(side, sizes, chord_tolerance);
            side.windows(2)
                .zip(&spacing)
                .map(|(w, h)| w[0].distance(w[1]) / h.max(f64::MIN_POSITIVE))
                .collect()
        })
        .collect();
    let mut pieces: Vec<usize> = measures
        .iter()
        .map(|m| (m.iter().sum::<f64>().round() as usize).max(1))
        .collect();
    // A loop needs at least four nodes, and an even count.
    while pieces.iter().sum::<usize>() < 4 || pieces.iter().sum::<usize>() % 2 == 1 {
        let longest = (0..pieces.len())
            .max_by(|&a, &b| {
                (lengths[a] / pieces[a] as f64).total_cmp(&(lengths[b] / pieces[b] as f64))
            })
            .unwrap_or(0);
        pieces[longest] += 1;
    }
    let mut nodes = Vec::with_capacity(pieces.iter().sum());
    for (side, (&count, measure)) in sides.iter().zip(pieces.iter().zip(&measures)) {
        nodes.push(side[0]);
        let total: f64 = measure.iter().sum();
        let mut walked = 0.0;
        let mut seg = 0;
        for k in 1..count {
            let target = total * k as f64 / count as f64;
            while seg + 1 < measure.len() && walked + measure[seg] < target {
                walked += measure[seg];
                seg += 1;
            }
            let (a, b) = (side[seg], side[seg + 1]);
            let t = (target - walked) / measure[seg].max(f64::MIN_POSITIVE);
            nodes.push(a.lerp(b, t.clamp(0.0, 1.0)));
        }
    }
    nodes
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_curve_is_cut_finely_enough_for_its_sag() {
        // A slot: two straight sides and two half circles of 12 mm, one smooth loop.
        let r = 12.0;
        let mut slot: Vec<DVec2> = Vec::new();
        for end in [0.0, 1.0] {
            let centre = DVec2::new(if end == 0.0 { 48.0 } else { -48.0 }, 0.0);
            for k in 0..=32 {
                let t =
                    -std::f64::consts::FRAC_PI_2 + std::f64::consts::PI * (end + k as f64 / 32.0);
                slot.push(centre + r * DVec2::new(t.cos(), t.sin()));
            }
        }
        let tolerance = 0.5;
        let nodes = place_nodes(&slot, Sizes::uniform(20.0), 1.0, tolerance);
        // Every piece's chord within the tolerance of the arc (its midpoint's distance
        // from the nearer end's circle centre; a fifth more for a piece running from the
        // straight onto the arc), and the straight sides in pieces of at most 20.
        for k in 0..nodes.len() {
            let (a, b) = (nodes[k], nodes[(k + 1) % nodes.len()]);
            let mid = a.lerp(b, 0.5);
            if mid.x.abs() > 48.0 {
                let centre = DVec2::new(48f64.copysign(mid.x), 0.0);
                let on_arc = a.x.abs() >= 48.0 && b.x.abs() >= 48.0;
                let allowed = if on_arc { tolerance } else { 1.2 * tolerance };
                assert!(r - mid.distance(centre) <= allowed + 1e-6, "{a} {b}");
            } else {
                assert!(a.distance(b) <= 20.0 + 1e-9);
            }
        }
        assert_eq!(nodes.len() % 2, 0);
    }

    #[test]
    fn a_square_gets_its_corners_and_even_sides() {
        let square = [
            DVec2::new(0.0, 0.0),
            DVec2::new(10.0, 0.0),
            DVec2::new(10.0, 10.0),
            DVec2::new(0.0, 10.0),
        ];
        let nodes = place_nodes(&square, Sizes::uniform(2.0), 0.5, 0.1);
        assert_eq!(nodes.len(), 20);
        for c in square {
            assert!(nodes.iter().any(|n| n.distance(c) < 1e-12));
        }
    }

    #[test]
    fn an_odd_count_is_made_even_on_the_longest_pieces() {
        let tri = [
            DVec2::new(0.0, 0.0),
            DVec2::new(10.0, 0.0),
            DVec2::new(0.0, 10.0),
        ];
        let nodes = place_nodes(&tri, Sizes::uniform(3.0), 0.5, 0.1);
        // 3 + 3 + 5 pieces is odd: a leg (3.3 mm pieces against 2.8) gets one more.
        assert_eq!(nodes.len(), 12);
    }
}
