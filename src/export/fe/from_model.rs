//! The die model as an FE deck's data: every meshed part (a `quad_mesh`, a mesh read or
//! made in the script) one shell part, every line bead a bead.
//!
//! Nodes that coincide (within [`WELD`]) are one node across all parts, so two parts
//! meshed to share their seam's nodes share them in the deck. Each part's shells are
//! turned, as a whole, to face up (+Z: the mean of their normals), as the writers
//! expect. Surfaces the script did not mesh are not in the deck: a shell deck holds
//! elements, and which size to mesh a surface at is the designer's decision.

use std::collections::{HashMap, HashSet};
use std::hash::{BuildHasherDefault, Hasher};

use glam::DVec3;
use rayon::prelude::*;

use super::{FeBead, FeModel, FePart, Shell};
use crate::die::model::{DieModel, Part, Shape};

/// Nodes nearer than this (mm) are one node.
pub const WELD: f64 = 1e-6;

/// The shell thickness written for every part (mm): the die face is a rigid tool, and
/// its contact takes the blank's thickness, not the tool's.
pub const TOOL_THICKNESS: f64 = 1.0;

/// Node ids by position: a point within [`WELD`] of a node already placed is that node
/// (found among the grid cells of size [`WELD`] round it, so two points straddling a
/// cell's edge still meet).
///
/// Most points of a deck have no other point near them, and searching the 27 cells of
/// each in a map of every node made half of writing a 131,000-node deck (a cache miss
/// per look-up). So the cells are grouped in blocks of `2^BLOCK_BITS` a side (about a
/// micrometre), and before any look-up the blocks holding two or more of the points to
/// be looked up are found ([`Nodes::for_points`]). A point alone in its block and not
/// in a cell on the block's edge has no other point within a cell of its own, so no
/// look-up ever finds it nor it any node: it becomes a node without the map. Only the
/// others (the seams' nodes, met once from each side) search and join the map, which
/// numbers every node as searching for all of them would.
struct Nodes {
    points: Vec<DVec3>,
    by_cell: HashMap<(i64, i64, i64), u32, BuildHasherDefault<CellHasher>>,
    crowded: HashSet<(i64, i64, i64), BuildHasherDefault<CellHasher>>,
}

/// A weld block's side is `2^BLOCK_BITS` cells (a power of two: a cell's block is its
/// key shifted, rounding down for negative keys too).
const BLOCK_BITS: u32 = 10;

/// The weld cell of a point.
fn cell_of(p: DVec3) -> (i64, i64, i64) {
    let cell = (p / WELD).round();
    (cell.x as i64, cell.y as i64, cell.z as i64)
}

/// The weld block holding the cell `key`.
fn block_of(key: (i64, i64, i64)) -> (i64, i64, i64) {
    (
        key.0 >> BLOCK_BITS,
        key.1 >> BLOCK_BITS,
        key.2 >> BLOCK_BITS,
    )
}

/// Whether the cell `key` lies on its block's edge (a cell beside it is in another
/// block).
fn on_block_edge(key: (i64, i64, i64)) -> bool {
    let last = (1 << BLOCK_BITS) - 1;
    [key.0, key.1, key.2]
        .iter()
        .any(|&c| c & last == 0 || c & last == last)
}

/// The weld grid's hasher: FxHash's rotate, xor and multiply per word of the cell key.
/// The standard SipHash, which guards a map against keys chosen to collide, made the
/// 27 look-ups per node a third of writing a deck; the map is only looked up, never
/// walked, so the deck does not depend on the hash.
#[derive(Default)]
struct CellHasher(u64);

impl Hasher for CellHasher {
    fn write(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.add(u64::from(b));
        }
    }

    fn write_i64(&mut self, word: i64) {
        self.add(word as u64);
    }

    fn finish(&self) -> u64 {
        self.0
    }
}

impl CellHasher {
    /// One word mixed in (FxHash's constant: odd, its bits spread).
    fn add(&mut self, word: u64) {
        self.0 = (self.0.rotate_left(5) ^ word).wrapping_mul(0x51_7c_c1_b7_27_22_0a_95);
    }
}

impl Nodes {
    /// Node ids for looking up any of `points` (every point that will be looked up
    /// must be among them, as often as it will be).
    fn for_points(points: &[DVec3]) -> Nodes {
        // Side by side: a deck has a hundred thousand points and more.
        let mut blocks: Vec<(i64, i64, i64)> =
            points.par_iter().map(|&p| block_of(cell_of(p))).collect();
        blocks.par_sort_unstable();
        let crowded = blocks
            .windows(2)
            .filter(|w| w[0] == w[1])
            .map(|w| w[0])
            .collect();
        Nodes {
            points: Vec::with_capacity(blocks.len()),
            by_cell: Default::default(),
            crowded,
        }
    }

    fn id(&mut self, p: DVec3) -> u32 {
        let key = cell_of(p);
        let alone = !on_block_edge(key) && !self.crowded.contains(&block_of(key));
        if !alone {
            if let Some(id) = self.near(key, p) {
                return id;
            }
        }
        let id = self.points.len() as u32;
        self.points.push(p);
        if !alone {
            self.by_cell.entry(key).or_insert(id);
        }
        id
    }

    /// The first node within [`WELD`] of `p` among the 27 cells round `key`.
    fn near(&self, key: (i64, i64, i64), p: DVec3) -> Option<u32> {
        for dx in -1..=1 {
            for dy in -1..=1 {
                for dz in -1..=1 {
                    let near = (key.0 + dx, key.1 + dy, key.2 + dz);
                    if let Some(&id) = self.by_cell.get(&near) {
                        if self.points[id as usize].distance(p) <= WELD {
                            return Some(id);
                        }
                    }
                }
            }
        }
        None
    }
}

/// The deck's data of `model`, titled `title`: one part per meshed part (depth first,
/// in the model's order), one bead per line bead.
pub fn fe_model(model: &DieModel, title: &str) -> FeModel {
    let mut points = Vec::new();
    for part in &model.parts {
        points_of(part, &mut points);
    }
    let mut nodes = Nodes::for_points(&points);
    let mut parts = Vec::new();
    let mut beads = Vec::new();
    for part in &model.parts {
        collect(part, &mut nodes, &mut parts, &mut beads);
    }
    FeModel {
        title: title.to_string(),
        nodes: nodes.points,
        parts,
        beads,
    }
}

/// Every point [`collect`] may look up in `part` and its children: its mesh's
/// positions and its line bead's points.
fn points_of(part: &Part, out: &mut Vec<DVec3>) {
    if let Some(Shape::Mesh(mesh)) = &part.shape {
        out.extend_from_slice(mesh.positions());
    }
    if let Some(bead) = &part.line_bead {
        out.extend_from_slice(&bead.points);
    }
    for child in &part.children {
        points_of(child, out);
    }
}

fn collect(part: &Part, nodes: &mut Nodes, parts: &mut Vec<FePart>, beads: &mut Vec<FeBead>) {
    if let Some(Shape::Mesh(mesh)) = &part.shape {
        let positions = mesh.positions();
        let up: f64 = mesh
            .faces()
            .iter()
            .map(|f| {
                let ids = f.indices();
                let p = |k: usize| positions[ids[k] as usize];
                // The first three corners and the last (a quad's fourth; a triangle's
                // normal uses only the first three), with no list made per face.
                let p = [0, 1, 2, ids.len() - 1].map(p);
                let n = if ids.len() == 4 {
                    (p[2] - p[0]).cross(p[3] - p[1])
                } else {
                    (p[1] - p[0]).cross(p[2] - p[0])
                };
                n.z
            })
            .sum();
        // Each vertex's node, looked up once (at its first corner, so the numbering
        // is the one a lookup per corner gives).
        let mut node_of: Vec<Option<u32>> = vec![None; positions.len()];
        let shells: Vec<Shell> = mesh
            .faces()
            .iter()
            .map(|f| {
                let face = if up < 0.0 { f.reversed() } else { *f };
                let mut node = |v: u32| {
                    *node_of[v as usize].get_or_insert_with(|| nodes.id(positions[v as usize]))
                };
                match *face.indices() {
                    [a, b, c, d] => Shell::Quad([node(a), node(b), node(c), node(d)]),
                    [a, b, c] => Shell::Triangle([node(a), node(b), node(c)]),
                    // A face has three or four corners: `Face`'s constructors make no
                    // other. Every corner is looked up, in order, as for the others.
                    ref ids => {
                        let ids: Vec<u32> = ids.iter().map(|&v| node(v)).collect();
                        Shell::Triangle([ids[0], ids[1], ids[ids.len() - 1]])
                    }
                }
            })
            .collect();
        if !shells.is_empty() {
            parts.push(FePart {
                name: part.name.clone(),
                kind: part.kind.clone(),
                thickness: TOOL_THICKNESS,
                shells,
            });
        }
    }
    if let Some(bead) = &part.line_bead {
        let ids: Vec<u32> = bead.points.iter().map(|&p| nodes.id(p)).collect();
        if ids.len() >= 2 {
            beads.push(FeBead {
                name: part.name.clone(),
                nodes: ids,
                force: bead.force,
                depth: bead.depth,
            });
        }
    }
    for child in &part.children {
        collect(child, nodes, parts, beads);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn points_within_the_weld_distance_are_one_node_across_a_cell_edge() {
        // 0.49e-6 and 0.51e-6 round to different cells (0 and 1) but lie within WELD;
        // the same again inside a block, away from its edges.
        for x in [0.0, 5e-4] {
            let points = [0.49e-6, 0.51e-6, 3e-6].map(|dx| DVec3::new(x + dx, 0.2, 0.3));
            let mut nodes = Nodes::for_points(&points);
            let [a, b, c] = points.map(|p| nodes.id(p));
            assert_eq!(a, b);
            assert_ne!(a, c);
            assert_eq!(nodes.points.len(), 2);
        }
    }

    #[test]
    fn points_in_neighbouring_blocks_meet_and_lone_points_are_nodes() {
        // Cells 1023 and 1024 (blocks 0 and 1) lie within WELD of each other.
        let across = [1023.4e-6, 1024.3e-6].map(|x| DVec3::new(x, 7.0, 9.0));
        let lone = [DVec3::new(5.0, 5.0, 5.0), DVec3::new(10.0, 5.0, 5.0)];
        let all: Vec<DVec3> = across.iter().chain(&lone).copied().collect();
        let mut nodes = Nodes::for_points(&all);
        let ids: Vec<u32> = all.iter().map(|&p| nodes.id(p)).collect();
        assert_eq!(ids, [0, 0, 1, 2]);
        // The lone points never entered the map.
        assert_eq!(nodes.by_cell.len(), 1);
    }
}
