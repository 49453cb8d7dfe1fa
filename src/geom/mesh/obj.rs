//! A mesh read from Wavefront OBJ text, as an FE pre-processor reads it: one node per
//! `v` line, in file order, shared by every face that names it, whatever group the
//! face is in and whatever normal or texture coordinate the corner carries.
//!
//! A renderer's OBJ loader (tobj, which dieface used before) splits a vertex wherever
//! two corners give it different normals or texture coordinates, and numbers each
//! object or group apart. For drawing that is right; for an FE mesh it cuts the mesh
//! along every group border and flat-shaded facet, so a panel exported with one group
//! per CAD patch arrives as pieces with free edges that are not in the file. Here the
//! file's own node numbering is kept, and `o`/`g` lines only name face groups.
//!
//! Read: `v` (the first three numbers; a weight or colour after them is ignored),
//! `vn`, `f` (corners `v`, `v/vt`, `v//vn`, `v/vt/vn`, indices from 1, negative ones
//! counted back from the last line read), `o` and `g`, `#` comments and `\` line
//! continuations. Ignored: texture coordinates, materials (`mtllib` and `usemtl`: the
//! material library is never opened), smoothing groups, and point and line elements.

use std::collections::HashMap;

use glam::DVec3;

use super::{Face, FaceId, Mesh};
use crate::geom::error::GeomError;

/// The name of the group the faces before any `o` or `g` line belong to.
pub const DEFAULT_GROUP: &str = "unnamed_object";

/// Why OBJ text could not be read as a mesh.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ObjError {
    /// More `v` lines than the caller allows: reading stops there.
    #[error("more than {limit} vertices")]
    TooManyVertices { limit: usize },
    /// A line that is not OBJ as a mesh needs it (line numbers from 1).
    #[error("line {line}: {reason}")]
    Line { line: usize, reason: String },
    /// The lines read, but they do not make a valid mesh.
    #[error("{0}")]
    Mesh(#[from] GeomError),
}

/// What a face corner names: its node, and its normal where it gives one.
#[derive(Debug, Clone, Copy)]
struct Corner {
    node: u32,
    normal: Option<u32>,
}

/// The mesh in the OBJ text `text`, with at most `max_vertices` nodes.
///
/// Faces of three and four corners are kept as they are; a larger polygon becomes a
/// fan of triangles from its first corner. Each `o` or `g` line starts a face group of
/// the name that follows it (groups of the same name are one group; a group with no
/// faces is not made). Per-vertex normals are kept when every corner names one and the
/// corners at each node agree on it; a flat-shaded file (a normal per facet) has its
/// normals computed from the faces where they are needed instead.
pub fn parse_obj(text: &[u8], max_vertices: usize) -> Result<Mesh, ObjError> {
    let mut positions: Vec<DVec3> = Vec::new();
    let mut normals: Vec<DVec3> = Vec::new();
    let mut faces: Vec<Face> = Vec::new();
    // Each corner's node and normal, while every corner has named one.
    let mut corner_normals: Vec<(u32, u32)> = Vec::new();
    let mut every_corner_has_normal = true;
    // Groups in the order first named, each with its faces.
    let mut groups: Vec<(String, Vec<FaceId>)> = Vec::new();
    let mut current: Option<usize> = None;
    // Each group's index by name, for the `o` and `g` lines that name it again.
    let mut group_index: HashMap<String, usize> = HashMap::new();
    let mut corners: Vec<Corner> = Vec::new();
    let mut nodes: Vec<u32> = Vec::new();
    let mut joined = String::new();
    // The farthest node a face names, and the line of the first face to name it.
    let mut farthest: Option<(u32, usize)> = None;

    let mut lines = text.split(|&b| b == b'\n').enumerate();
    while let Some((at, raw)) = lines.next() {
        let line_number = at + 1;
        let fail = |reason: String| ObjError::Line {
            line: line_number,
            reason,
        };
        let mut line = as_text(raw).map_err(&fail)?;
        // A line ending in a backslash goes on on the next.
        if line.ends_with('\\') {
            joined.clear();
            joined.push_str(&line[..line.len() - 1]);
            for (_, more) in lines.by_ref() {
                let more = as_text(more).map_err(&fail)?;
                match more.strip_suffix('\\') {
                    Some(head) => {
                        joined.push(' ');
                        joined.push_str(head);
                    }
                    None => {
                        joined.push(' ');
                        joined.push_str(more);
                        break;
                    }
                }
            }
            line = joined.as_str();
        }
        let line = line.split('#').next().unwrap_or("").trim();
        let mut words = line.split_ascii_whitespace();
        let Some(keyword) = words.next() else {
            continue;
        };
        match keyword {
            "v" => {
                if positions.len() == max_vertices {
                    return Err(ObjError::TooManyVertices {
                        limit: max_vertices,
                    });
                }
                positions.push(three_numbers(&mut words).map_err(fail)?);
            }
            "vn" => normals.push(three_numbers(&mut words).map_err(fail)?),
            "f" => {
                corners.clear();
                for word in words {
                    corners.push(corner(word, positions.len(), normals.len()).map_err(&fail)?);
                }
                if corners.len() < 3 {
                    return Err(fail(format!(
                        "a face needs three corners or more, this one has {}",
                        corners.len()
                    )));
                }
                let group = *current.get_or_insert_with(|| {
                    group_named(DEFAULT_GROUP, &mut groups, &mut group_index)
                });
                let first_face = faces.len();
                nodes.clear();
                nodes.extend(corners.iter().map(|c| c.node));
                for &v in &nodes {
                    if farthest.is_none_or(|(far, _)| v > far) {
                        farthest = Some((v, line_number));
                    }
                }
                if let Some(k) = (1..nodes.len()).find(|&k| nodes[..k].contains(&nodes[k])) {
                    return Err(fail(format!(
                        "the face names vertex {} twice",
                        nodes[k] + 1
                    )));
                }
                if nodes.len() <= 4 {
                    // Three or four corners, checked above.
                    faces.push(Face::from_slice(&nodes).map_err(|e| fail(e.to_string()))?);
                } else {
                    faces.extend(
                        (1..nodes.len() - 1)
                            .map(|k| Face::triangle(nodes[0], nodes[k], nodes[k + 1])),
                    );
                }
                every_corner_has_normal &= corners.iter().all(|c| c.normal.is_some());
                if every_corner_has_normal {
                    corner_normals.extend(corners.iter().filter_map(|c| Some((c.node, c.normal?))));
                } else {
                    corner_normals = Vec::new();
                }
                groups[group]
                    .1
                    .extend((first_face..faces.len()).map(|f| FaceId(f as u32)));
            }
            "o" | "g" => {
                let name = line[keyword.len()..].trim();
                let name = if name.is_empty() { DEFAULT_GROUP } else { name };
                current = Some(group_named(name, &mut groups, &mut group_index));
            }
            // Texture coordinates, parameter-space vertices, materials, smoothing
            // groups, points, lines and the rest of the format: nothing a mesh keeps.
            _ => {}
        }
    }
    // A node that a face names must exist by the end of the file (a positive index may
    // name a `v` line further down, as most readers allow): the face naming the
    // farthest node is the one to show.
    let count = positions.len();
    if let Some((node, line)) = farthest.filter(|&(node, _)| node as usize >= count) {
        return Err(ObjError::Line {
            line,
            reason: format!(
                "the face names vertex {}, but the file has {count}",
                node + 1
            ),
        });
    }
    // The nodes were checked against the count just above.
    let normals = if every_corner_has_normal && !faces.is_empty() {
        node_normals(&corner_normals, &normals, count)
    } else {
        None
    };
    let mut mesh = Mesh::new(positions, faces)?;
    if let Some(normals) = normals {
        mesh = mesh.with_normals(normals)?;
    }
    for (name, faces) in groups {
        if !faces.is_empty() {
            mesh.add_group(name, faces)?;
        }
    }
    Ok(mesh)
}

/// The index of the group called `name`, made (with no faces yet) where there is none.
fn group_named(
    name: &str,
    groups: &mut Vec<(String, Vec<FaceId>)>,
    index: &mut HashMap<String, usize>,
) -> usize {
    *index.entry(name.to_string()).or_insert_with(|| {
        groups.push((name.to_string(), Vec::new()));
        groups.len() - 1
    })
}

/// A line as text: OBJ is ASCII, and a group name may be UTF-8. A carriage return
/// before the line's end is dropped.
fn as_text(raw: &[u8]) -> Result<&str, String> {
    let raw = raw.strip_suffix(b"\r").unwrap_or(raw);
    std::str::from_utf8(raw).map_err(|e| format!("not UTF-8 text (byte {})", e.valid_up_to() + 1))
}

/// The first three numbers of a `v` or `vn` line.
fn three_numbers<'a>(words: &mut impl Iterator<Item = &'a str>) -> Result<DVec3, String> {
    let mut xyz = [0.0; 3];
    for (k, slot) in xyz.iter_mut().enumerate() {
        let word = words
            .next()
            .ok_or_else(|| format!("three coordinates expected, found {k}"))?;
        *slot = word
            .parse::<f64>()
            .map_err(|_| format!("`{word}` is not a number"))?;
        if !slot.is_finite() {
            return Err(format!("`{word}` is not a finite number"));
        }
    }
    Ok(DVec3::from_array(xyz))
}

/// A face corner `v`, `v/vt`, `v//vn` or `v/vt/vn`, with `nodes` and `normals` read so
/// far (for indices counted back from the end).
fn corner(word: &str, nodes: usize, normals: usize) -> Result<Corner, String> {
    let mut parts = word.split('/');
    let node = index(parts.next().unwrap_or(""), nodes, "vertex", word)?;
    // The texture coordinate is not kept, but must be a number where given.
    if let Some(vt) = parts.next() {
        if !vt.is_empty() && vt.parse::<i64>().is_err() {
            return Err(format!(
                "the corner `{word}` has a texture index that is not a number"
            ));
        }
    }
    let normal = match parts.next() {
        Some(vn) if !vn.is_empty() => Some(index(vn, normals, "normal", word)?),
        _ => None,
    };
    if parts.next().is_some() {
        return Err(format!("the corner `{word}` has more than three indices"));
    }
    if let Some(n) = normal {
        if n as usize >= normals {
            return Err(format!(
                "the corner `{word}` names normal {}, but {normals} are given before it",
                n + 1
            ));
        }
    }
    Ok(Corner { node, normal })
}

/// A 1-based OBJ index as a 0-based one; a negative index counts back from `count`,
/// the items read so far.
fn index(word: &str, count: usize, what: &str, corner: &str) -> Result<u32, String> {
    let i: i64 = word
        .parse()
        .map_err(|_| format!("the corner `{corner}` has a {what} index that is not a number"))?;
    let zero_based = match i {
        0 => {
            return Err(format!(
                "the corner `{corner}` names {what} 0 (OBJ counts from 1)"
            ))
        }
        i if i > 0 => i - 1,
        i => count as i64 + i,
    };
    if zero_based < 0 {
        return Err(format!(
            "the corner `{corner}` counts back past the first {what} ({count} read before it)"
        ));
    }
    u32::try_from(zero_based)
        .map_err(|_| format!("the corner `{corner}` names a {what} past any mesh's size"))
}

/// One normal per node from each corner's `(node, normal)`, where the corners at every
/// node agreed on one (a node no face names gets the zero vector); `None` where they
/// did not. Every node is below `nodes` and every normal index in `normals`: both were
/// checked as the lines were read.
fn node_normals(corners: &[(u32, u32)], normals: &[DVec3], nodes: usize) -> Option<Vec<DVec3>> {
    // The normal each node's corners named, once one has.
    let mut at: Vec<Option<u32>> = vec![None; nodes];
    for &(v, n) in corners {
        match at[v as usize] {
            None => at[v as usize] = Some(n),
            Some(m) if m == n => {}
            // Two normals at one node: a crease, or a flat-shaded facet.
            Some(_) => return None,
        }
    }
    Some(
        at.into_iter()
            .map(|n| n.map_or(DVec3::ZERO, |n| normals[n as usize].normalize_or_zero()))
            .collect(),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    fn read(text: &str) -> Mesh {
        parse_obj(text.as_bytes(), usize::MAX).expect("reads")
    }

    #[test]
    fn groups_share_the_files_nodes() {
        // Two groups meeting along the edge 2-3: one node each, as in the file.
        let mesh = read("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\ng left\nf 1 2 3\ng right\nf 1 3 4\n");
        assert_eq!(mesh.vertex_count(), 4);
        assert_eq!(mesh.faces()[1].indices(), &[0, 2, 3]);
        let names: Vec<&str> = mesh.groups().iter().map(|g| g.name()).collect();
        assert_eq!(names, ["left", "right"]);
        assert_eq!(
            mesh.topology().free_edges().len(),
            4,
            "only the square's sides"
        );
    }

    #[test]
    fn flat_shaded_corners_keep_one_node_and_drop_the_normals() {
        let mesh = read("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvn 0 0 1\nvn 0 0.1 1\nf 1//1 2//1 3//1\nf 1//2 3//2 4//2\n");
        assert_eq!(mesh.vertex_count(), 4);
        assert!(mesh.normals().is_none(), "two normals at node 1");
        assert_eq!(mesh.topology().free_edges().len(), 4);
    }

    #[test]
    fn agreeing_normals_are_kept_per_node() {
        let mesh = read("v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 2\nf 1/7/1 2/7/1 3//1\n");
        let normals = mesh.normals().expect("one normal per node");
        assert!(normals.iter().all(|&n| n == DVec3::Z));
    }

    #[test]
    fn negative_indices_count_back_and_polygons_become_fans() {
        let mesh = read(
            "v 0 0 0\nv 2 0 0\nv 3 1 0\nv 1 2 0\nv -1 1 0\nf -5 -4 -3 -2 -1\ng quad\nf 1 2 3 4\n",
        );
        assert_eq!(mesh.triangle_and_quad_counts(), (3, 1));
        assert_eq!(mesh.faces()[2].indices(), &[0, 3, 4]);
        let names: Vec<&str> = mesh.groups().iter().map(|g| g.name()).collect();
        assert_eq!(names, [DEFAULT_GROUP, "quad"]);
    }

    #[test]
    fn continuations_comments_and_other_elements_are_read_past() {
        let text = "mtllib ../../elsewhere.mtl\n# a comment\nv 0 0 0 1.0 # weight\nv 1 0 0\r\nv 0 1 \\\n 0\nvt 0 0\nusemtl steel\ns off\nl 1 2\nf 1/1 2/1 3/1\n";
        let mesh = read(text);
        assert_eq!(mesh.vertex_count(), 3);
        assert_eq!(mesh.positions()[2], DVec3::new(0.0, 1.0, 0.0));
        assert_eq!(mesh.face_count(), 1);
    }

    #[test]
    fn bad_lines_are_named_by_number() {
        let line_of = |text: &str| match parse_obj(text.as_bytes(), usize::MAX) {
            Err(ObjError::Line { line, .. }) => line,
            other => panic!("{text:?} gave {other:?}"),
        };
        assert_eq!(line_of("v 0 0 0\nv 1 x 0\n"), 2);
        assert_eq!(line_of("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2\n"), 4);
        assert_eq!(line_of("v 0 0 0\nf 0 1 2\n"), 2);
        assert_eq!(line_of("v 0 0 0\nf -2 1 1\n"), 2);
        assert_eq!(line_of("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1//1 2//1 3//1\n"), 4);
        assert_eq!(line_of("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 2\n"), 4);
        assert_eq!(line_of("v 0 0 inf\n"), 1);
        // A node far past the file, with a normal: refused, not a table that large.
        assert_eq!(
            line_of("v 0 0 0\nv 1 0 0\nvn 0 0 1\nf 1//1 2//1 4000000000//1\n"),
            4
        );
    }

    #[test]
    fn a_face_past_the_last_vertex_and_too_many_vertices_are_refused() {
        let text = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\nf 4 2 1\n";
        assert!(matches!(
            parse_obj(text.as_bytes(), usize::MAX),
            Err(ObjError::Line { line: 4, .. })
        ));
        assert_eq!(
            parse_obj(text.as_bytes(), 2),
            Err(ObjError::TooManyVertices { limit: 2 })
        );
    }

    proptest::proptest! {
        /// Text made of OBJ's own words in any order, indices out of range or huge
        /// included, is read or refused, never a panic.
        #[test]
        fn any_obj_like_text_is_read_or_refused(
            words in proptest::collection::vec(proptest::sample::select(vec![
                "v", "vn", "vt", "f", "g", "o", "\\", "\n", "\n", "#", "1", "2", "3", "-1", "-4",
                "0", "0.5", "1e400", "nan", "4294967296", "4294967295", "2/1", "3//1", "1/1/1",
                "1//9", "4294967294//1", "//", "/", "a", "\r\n", "\u{e9}",
            ]), 0..60),
        ) {
            let text = words.join(" ");
            let _ = parse_obj(text.as_bytes(), 16);
            let _ = parse_obj(text.as_bytes(), usize::MAX);
        }

        /// Any mesh written as OBJ (every corner with a texture index and its face's
        /// normal, faces split among groups) reads back with the same nodes, in order,
        /// the same faces and the same groups.
        #[test]
        fn a_written_mesh_reads_back_node_for_node(
            points in proptest::collection::vec((-1e3f64..1e3, -1e3f64..1e3, -1e3f64..1e3), 4..30),
            picks in proptest::collection::vec((0usize..1000, 0usize..1000, 0usize..1000, 0usize..1000, proptest::bool::ANY, 0usize..3), 1..40),
        ) {
            let n = points.len();
            let mut text = String::new();
            for &(x, y, z) in &points {
                text.push_str(&format!("v {x:?} {y:?} {z:?}\n"));
            }
            let mut faces: Vec<(Vec<u32>, usize)> = Vec::new();
            for &(a, b, c, d, quad, group) in &picks {
                let mut corners: Vec<u32> = Vec::new();
                for i in [a, b, c, d].into_iter().take(if quad { 4 } else { 3 }) {
                    let v = (i % n) as u32;
                    if !corners.contains(&v) {
                        corners.push(v);
                    }
                }
                if corners.len() >= 3 {
                    faces.push((corners, group));
                }
            }
            proptest::prop_assume!(!faces.is_empty());
            for (k, (corners, group)) in faces.iter().enumerate() {
                text.push_str(&format!("vn 0 0 1\ng part{group}\nf"));
                for &v in corners {
                    text.push_str(&format!(" {}/{}/{}", v + 1, k + 1, k + 1));
                }
                text.push('\n');
            }
            let mesh = parse_obj(text.as_bytes(), usize::MAX).expect("reads");
            let expected: Vec<DVec3> = points.iter().map(|&(x, y, z)| DVec3::new(x, y, z)).collect();
            proptest::prop_assert_eq!(mesh.positions(), &expected[..]);
            let read: Vec<Vec<u32>> = mesh.faces().iter().map(|f| f.indices().to_vec()).collect();
            let written: Vec<Vec<u32>> = faces.iter().map(|(c, _)| c.clone()).collect();
            proptest::prop_assert_eq!(read, written);
            for group in mesh.groups() {
                let k: usize = group.name()["part".len()..].parse().expect("a part number");
                for f in group.faces() {
                    proptest::prop_assert_eq!(faces[f.index()].1, k);
                }
            }
            let grouped: usize = mesh.groups().iter().map(|g| g.faces().len()).sum();
            proptest::prop_assert_eq!(grouped, faces.len());
        }
    }
}
