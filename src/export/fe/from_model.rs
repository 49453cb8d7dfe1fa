//! The die model as an FE deck's data: every meshed part (a `quad_mesh`, a mesh read or
//! made in the script) one shell part, every line bead a bead.
//!
//! Nodes that coincide (within [`WELD`]) are one node across all parts, so two parts
//! meshed to share their seam's nodes share them in the deck. Each part's shells are
//! turned, as a whole, to face up (+Z: the mean of their normals), as the writers
//! expect. Surfaces the script did not mesh are not in the deck: a shell deck holds
//! elements, and which size to mesh a surface at is the designer's decision.

use std::collections::HashMap;
use std::hash::{BuildHasherDefault, Hasher};

use glam::DVec3;

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
#[derive(Default)]
struct Nodes {
    points: Vec<DVec3>,
    by_cell: HashMap<(i64, i64, i64), u32, BuildHasherDefault<CellHasher>>,
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
    fn id(&mut self, p: DVec3) -> u32 {
        let cell = (p / WELD).round();
        let key = (cell.x as i64, cell.y as i64, cell.z as i64);
        for dx in -1..=1 {
            for dy in -1..=1 {
                for dz in -1..=1 {
                    let near = (key.0 + dx, key.1 + dy, key.2 + dz);
                    if let Some(&id) = self.by_cell.get(&near) {
                        if self.points[id as usize].distance(p) <= WELD {
                            return id;
                        }
                    }
                }
            }
        }
        let id = self.points.len() as u32;
        self.points.push(p);
        self.by_cell.entry(key).or_insert(id);
        id
    }
}

/// The deck's data of `model`, titled `title`: one part per meshed part (depth first,
/// in the model's order), one bead per line bead.
pub fn fe_model(model: &DieModel, title: &str) -> FeModel {
    let mut nodes = Nodes::default();
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
                let ids: Vec<u32> = face
                    .indices()
                    .iter()
                    .map(|&v| {
                        *node_of[v as usize].get_or_insert_with(|| nodes.id(positions[v as usize]))
                    })
                    .collect();
                match ids.as_slice() {
                    [a, b, c, d] => Shell::Quad([*a, *b, *c, *d]),
                    [a, b, c] => Shell::Triangle([*a, *b, *c]),
                    // A face has three or four corners: `Face`'s constructors make no other.
                    _ => Shell::Triangle([ids[0], ids[1], ids[ids.len() - 1]]),
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
        let mut nodes = Nodes::default();
        // 0.49e-6 and 0.51e-6 round to different cells (0 and 1) but lie within WELD.
        let a = nodes.id(DVec3::new(0.49e-6, 0.0, 0.0));
        let b = nodes.id(DVec3::new(0.51e-6, 0.0, 0.0));
        let c = nodes.id(DVec3::new(3e-6, 0.0, 0.0));
        assert_eq!(a, b);
        assert_ne!(a, c);
        assert_eq!(nodes.points.len(), 2);
    }
}
