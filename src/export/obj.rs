//! Wavefront OBJ writer.
//!
//! OBJ has no unit or axis convention, so the file keeps the die's own: millimetres in
//! press coordinates (+Z up), as the header comment says. Every node with geometry
//! starts an object and a group of the same name (`o pol/side-front`, `g pol/side-front`:
//! importers differ in which of the two they split by); nested names keep the '/' path.
//! A piece whose triangles are grouped (a solid's faces) writes each group after
//! `g node/group` (`g bracket/solid/plate_top`). Triangles are `f a//a b//b c//c`
//! (positions and normals share indices), curves are
//! `l` polylines. Numbers are printed with six decimals (nanometres), a fixed format so
//! the same scene always gives the same bytes.

use std::fmt::Write;

use glam::DVec3;

use super::scene::{Geometry, Scene};

/// The scene as OBJ text (UTF-8, `\n` line ends).
pub fn encode_obj(scene: &Scene) -> Vec<u8> {
    let mut out = String::new();
    let _ = writeln!(
        out,
        "# dieface {} export of {}",
        env!("CARGO_PKG_VERSION"),
        scene.source_name
    );
    out.push_str("# units: millimetres, press coordinates (x, y, z), +Z up;\n");
    out.push_str("# OBJ has no unit convention: scale by 0.001 for metres.\n");
    let _ = writeln!(out, "# chordal tolerance: {} mm", scene.tolerance_mm);
    // OBJ indices are 1-based and global to the file.
    let mut next_vertex = 1usize;
    for node in scene.all_nodes() {
        let geometry = node.primitives();
        if geometry.is_empty() {
            continue;
        }
        let name = obj_name(&node.name);
        let _ = writeln!(out, "o {name}\ng {name}");
        let _ = writeln!(out, "# kind: {}, line: {}", node.kind, node.line);
        for g in geometry {
            match g {
                Geometry::Triangles {
                    positions,
                    normals,
                    indices,
                    groups,
                } => {
                    for &p in positions {
                        vector(&mut out, "v", p);
                    }
                    for i in 0..positions.len() {
                        let n = normals.get(i).copied().unwrap_or(DVec3::Z);
                        vector(&mut out, "vn", n.try_normalize().unwrap_or(DVec3::Z));
                    }
                    let triangle = |out: &mut String, t: usize| {
                        let [a, b, c] =
                            [0, 1, 2].map(|k| indices[3 * t + k] as usize + next_vertex);
                        let _ = writeln!(out, "f {a}//{a} {b}//{b} {c}//{c}");
                    };
                    // Triangles in no group first, under the node's own group; then each
                    // group's under `g node/group`.
                    let mut grouped = vec![false; indices.len() / 3];
                    for g in groups {
                        for &t in &g.triangles {
                            if let Some(slot) = grouped.get_mut(t as usize) {
                                *slot = true;
                            }
                        }
                    }
                    for (t, _) in grouped.iter().enumerate().filter(|(_, &g)| !g) {
                        triangle(&mut out, t);
                    }
                    for g in groups {
                        let _ = writeln!(out, "g {name}/{}", obj_name(&g.name));
                        for &t in &g.triangles {
                            if (t as usize) < grouped.len() {
                                triangle(&mut out, t as usize);
                            }
                        }
                    }
                    next_vertex += positions.len();
                }
                Geometry::LineStrip { points } => {
                    for &p in points {
                        vector(&mut out, "v", p);
                    }
                    out.push('l');
                    for i in 0..points.len() {
                        let _ = write!(out, " {}", next_vertex + i);
                    }
                    out.push('\n');
                    next_vertex += points.len();
                }
            }
        }
    }
    out.into_bytes()
}

/// A name usable after `o` / `g`: whitespace (which would split it) becomes `_`.
fn obj_name(name: &str) -> String {
    name.chars()
        .map(|c| if c.is_whitespace() { '_' } else { c })
        .collect()
}

/// `tag x y z` with six decimals and no negative zero.
fn vector(out: &mut String, tag: &str, v: DVec3) {
    out.push_str(tag);
    for c in [v.x, v.y, v.z] {
        let s = format!("{c:.6}");
        let s = if s == "-0.000000" { "0.000000" } else { &s };
        out.push(' ');
        out.push_str(s);
    }
    out.push('\n');
}
