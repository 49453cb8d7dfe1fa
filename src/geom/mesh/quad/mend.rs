//! Folded quads mended by meshing the cavity round their inner node again.
//!
//! Smoothing and edge swaps leave a quad folded where its topology fixes its shape: a
//! quad on three neighbouring nodes of a nearly straight stretch of a loop, whose inner
//! corner fans out to the boundary because the loop's nodes lie much closer there than
//! the elements behind them (a seam crowded by a band's columns in a plan corner). No
//! swap with one neighbour mends it when the neighbours also sit on the boundary. The
//! quads round the folded quad's inner node make a polygon with an even count of
//! nodes; that polygon is split down again as a region of its own (its nodes kept),
//! which can give the middle boundary node an element of its own, and the new quads
//! are kept where their worst is no longer folded and better than the old worst.

use glam::DVec2;

use super::quality::{scaled_jacobian_2d, worst_quad_2d};
use super::sizing::Sizes;
use super::smooth::smooth;
use super::split::split_down;

/// Smoothing passes over a cavity's new inner nodes after it is split again.
const RELAX: usize = 8;

/// The polygon round inner node `i` of the counter-clockwise quads `star` (those
/// holding it), counter-clockwise, or `None` where they do not close round it once.
fn cavity_polygon(quads: &[[u32; 4]], star: &[usize], i: u32) -> Option<Vec<u32>> {
    // Each quad as (a, b, c) after `i`, keyed by `a`: the next quad round `i` starts
    // where this one's `c` is.
    let turned: Vec<[u32; 3]> = star
        .iter()
        .map(|&k| {
            let q = quads[k];
            let at = q.iter().position(|&v| v == i)?;
            Some([q[(at + 1) % 4], q[(at + 2) % 4], q[(at + 3) % 4]])
        })
        .collect::<Option<_>>()?;
    let mut polygon = Vec::with_capacity(2 * turned.len());
    let mut at = turned[0];
    for _ in 0..turned.len() {
        polygon.extend([at[0], at[1]]);
        at = *turned.iter().find(|t| t[0] == at[2])?;
    }
    // Back at the first quad, with every node met once.
    let mut sorted = polygon.clone();
    sorted.sort_unstable();
    let distinct = sorted.windows(2).all(|w| w[0] != w[1]);
    (at == turned[0] && distinct && !polygon.contains(&i)).then_some(polygon)
}

/// Mends every quad poorer than `folded` (plane scaled Jacobian) that has an inner
/// node held by quads alone (the first `fixed` nodes are the boundary's): the quads
/// round that node split down again as one polygon (at `sizes`), their new inner nodes
/// smoothed, kept where the new worst quad beats both `folded` and the old worst. The
/// node a mended cavity no longer uses is left out, and the nodes after it are
/// renumbered. Returns how many quads were mended.
pub fn mend_folded(
    points: &mut Vec<DVec2>,
    fixed: usize,
    quads: &mut Vec<[u32; 4]>,
    triangles: &mut [[u32; 3]],
    sizes: Sizes,
    folded: f64,
) -> usize {
    let poor: Vec<[u32; 4]> = quads
        .iter()
        .copied()
        .filter(|q| scaled_jacobian_2d(&q.map(|v| points[v as usize])) < folded)
        .collect();
    let mut dropped: Vec<u32> = Vec::new();
    let mut mended = 0;
    for q in poor {
        // Still there, and still folded (an earlier cavity may have taken it).
        if !quads.contains(&q) || worst_quad_2d(points, &[q]) >= folded {
            continue;
        }
        for i in q.into_iter().filter(|&v| v as usize >= fixed) {
            if triangles.iter().any(|t| t.contains(&i)) {
                continue;
            }
            let star: Vec<usize> = (0..quads.len())
                .filter(|&k| quads[k].contains(&i))
                .collect();
            let Some(polygon) = cavity_polygon(quads, &star, i) else {
                continue;
            };
            let old: Vec<[u32; 4]> = star.iter().map(|&k| quads[k]).collect();
            let before = worst_quad_2d(points, &old);
            let mut trial = points.clone();
            let first_new = trial.len();
            let (mut made, mut odd) = (Vec::new(), Vec::new());
            if split_down(&mut trial, polygon, sizes, &mut made, &mut odd).is_err()
                || !odd.is_empty()
                || made.is_empty()
            {
                continue;
            }
            // Only the new nodes move: the polygon's own are the cavity's boundary.
            smooth(&mut trial, first_new, &made, &[], RELAX);
            let after = worst_quad_2d(&trial, &made);
            if after < folded || after <= before {
                continue;
            }
            *points = trial;
            quads.retain(|k| !old.contains(k));
            quads.extend(made);
            dropped.push(i);
            mended += 1;
            break;
        }
    }
    if !dropped.is_empty() {
        left_out(points, quads, triangles, &dropped);
    }
    mended
}

/// `dropped` (nodes no element uses any more) taken out of `points`, the elements'
/// nodes renumbered to match.
fn left_out(
    points: &mut Vec<DVec2>,
    quads: &mut [[u32; 4]],
    triangles: &mut [[u32; 3]],
    dropped: &[u32],
) {
    let mut new_id = vec![u32::MAX; points.len()];
    let mut kept = Vec::with_capacity(points.len() - dropped.len());
    for (v, &p) in points.iter().enumerate() {
        if !dropped.contains(&(v as u32)) {
            new_id[v] = kept.len() as u32;
            kept.push(p);
        }
    }
    *points = kept;
    // No element holds a dropped node: its cavity's quads were all replaced.
    for v in quads
        .iter_mut()
        .flatten()
        .chain(triangles.iter_mut().flatten())
    {
        *v = new_id[*v as usize];
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A strip whose bottom has three nodes on a nearly straight line under one quad,
    /// its neighbours on the boundary too: no swap mends it, the cavity does.
    #[test]
    fn a_quad_on_three_straight_boundary_nodes_gets_its_middle_node_an_element() {
        // Boundary: 0..=4 along the bottom (bowed a little at 2), 5, 6, 7 along the top;
        // node 8 inside.
        let mut points = crate::geom::mesh::quad::split::tests::bowed_strip();
        points.push(DVec2::new(2.0, 1.0));
        // 8 joined to the boundary nodes 0, 1, 3, 4, 6: the quad 1 2 3 8 is straight at 2.
        let mut quads = vec![[0, 1, 8, 7], [1, 2, 3, 8], [3, 4, 5, 8], [8, 5, 6, 7]];
        let before = worst_quad_2d(&points, &quads);
        assert!(before < 0.1, "{before}");
        let mut triangles: Vec<[u32; 3]> = Vec::new();
        let mended = mend_folded(
            &mut points,
            8,
            &mut quads,
            &mut triangles,
            Sizes::uniform(1.0),
            0.1,
        );
        assert_eq!(mended, 1);
        let after = worst_quad_2d(&points, &quads);
        assert!(after > 0.3, "{before} -> {after}");
        // Node 2 now has a corner that is not straight, every node is used, and the
        // quads still cover the strip's area (8 mm^2 and the bow's sliver).
        let used: std::collections::BTreeSet<u32> = quads.iter().flatten().copied().collect();
        assert_eq!(used.len(), points.len());
        let area: f64 = quads
            .iter()
            .map(|q| crate::geom::trimmed::polygon_area(q.iter().map(|&v| points[v as usize])))
            .sum();
        assert!((area - (8.0 + 0.03)).abs() < 1e-9, "{area}");
    }

    #[test]
    fn good_quads_are_left_alone() {
        let mut points = vec![
            DVec2::new(0.0, 0.0),
            DVec2::new(1.0, 0.0),
            DVec2::new(2.0, 0.0),
            DVec2::new(2.0, 1.0),
            DVec2::new(1.0, 1.0),
            DVec2::new(0.0, 1.0),
        ];
        let mut quads = vec![[0, 1, 4, 5], [1, 2, 3, 4]];
        let kept = quads.clone();
        let mended = mend_folded(
            &mut points,
            6,
            &mut quads,
            &mut [],
            Sizes::uniform(1.0),
            0.1,
        );
        assert_eq!((mended, quads), (0, kept));
    }
}
