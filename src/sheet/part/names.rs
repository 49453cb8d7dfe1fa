//! The names of a plate part's solid faces, as a designer would call them: one mesh
//! group each (`plate.top`, `HOLE.wall_K`, `FLANGE.inside`, `LIFT.wall_K.top`, ...).

use super::super::topology::{EdgeRole, FaceId, FaceRole, Sheet, TopologyError, VertexId};
use super::{Cut, PlateSpec};

/// What the build made of each operation of a plate, for naming its faces: the
/// plate's cuts along bend creases, each hole's ring of vertices, each lifted region's
/// top with its walls, each flange's strips' sides (on a radius, the bend's facets
/// first), and each cover's inside and outside (`None` once removed).
#[derive(Clone, Copy)]
pub(super) struct Pieces<'a> {
    pub cuts: &'a [Cut],
    pub hole_rings: &'a [Vec<VertexId>],
    pub lifts: &'a [(FaceId, Vec<FaceId>)],
    pub flanges: &'a [Vec<(FaceId, FaceId)>],
    pub covers: &'a [Option<(FaceId, FaceId)>],
}

/// The name of each face of a plate's solid, as a designer would call it: `plate.top`
/// and `plate.bottom` (the top faces the working plane's normal), `plate.edge_K` across
/// the outline's edges, `HOLE.wall_K` lining a hole, and per flange `NAME.inside` (the
/// side that continues the plate's top, inside the bend), `NAME.outside` and
/// `NAME.edge_K`, and a bend's facets `NAME.bend_K.inside` and `.outside`, and per
/// cover `NAME.inside`, `NAME.outside` and `NAME.edge_K`; K counts
/// from 1 in the model's face order.
pub(super) struct FaceNames {
    names: std::collections::BTreeMap<FaceId, String>,
}
impl FaceNames {
    pub(super) fn new(
        sheet: &Sheet,
        spec: &PlateSpec,
        top: FaceId,
        pieces: &Pieces,
    ) -> Result<FaceNames, TopologyError> {
        let Pieces {
            cuts,
            hole_rings,
            lifts,
            flanges,
            covers,
        } = *pieces;
        let b = &sheet.brep;
        let mut names = std::collections::BTreeMap::new();
        // The plate's parts, named by the bend that turned them (the rest `plate`).
        let mut part_names = std::collections::BTreeMap::new();
        part_names.insert(top, "plate".to_string());
        for cut in cuts {
            let before = part_names.get(&cut.part).cloned().unwrap_or_default();
            part_names.insert(cut.fixed, before);
            part_names.insert(cut.moved, cut.name.clone());
        }
        for (&part, name) in &part_names {
            // A part removed (split off by a bend, then taken away) has no faces.
            let Ok(FaceRole::Side { twin }) = sheet.face_role(part) else {
                continue;
            };
            names.insert(part, format!("{name}.top"));
            names.insert(twin, format!("{name}.bottom"));
        }
        // The sides across the non-zero-length edges of face f.
        let neighbours = |f: FaceId| -> Result<Vec<FaceId>, TopologyError> {
            let mut out = Vec::new();
            for &l in b.loops_of(f)? {
                for h in b.loop_halves(l)? {
                    let Some(e) = b.edge(h)? else { continue };
                    if sheet.edge_role(e)? != EdgeRole::ZeroLength {
                        out.push(b.face_with(b.loop_with(b.mate(h)?)?)?);
                    }
                }
            }
            Ok(out)
        };
        // Each flange's last inside: where a return flange on it continues.
        let mut insides: Vec<Option<FaceId>> = Vec::with_capacity(flanges.len());
        for (k, strips) in flanges.iter().enumerate() {
            let name = &spec.flanges[k].name;
            // Each strip's inside continues the one before it (first the top of the
            // plate's part it stands on: bends split the plate into parts; for a return
            // flange, the inside of the flange it stands on).
            let parent = spec.flanges[k]
                .on
                .as_ref()
                .and_then(|p| spec.flanges[..k].iter().rposition(|f| &f.name == p));
            let mut before: Vec<FaceId> = match parent.and_then(|p| insides[p]) {
                Some(inside) => vec![inside],
                None => part_names.keys().copied().collect(),
            };
            for (i, &(a, c)) in strips.iter().enumerate() {
                let inside = if neighbours(a)?.iter().any(|f| before.contains(f)) {
                    a
                } else {
                    c
                };
                let outside = if inside == a { c } else { a };
                let part = if i + 1 == strips.len() {
                    name.clone()
                } else {
                    format!("{name}.bend_{}", i + 1)
                };
                names.insert(inside, format!("{part}.inside"));
                names.insert(outside, format!("{part}.outside"));
                before = vec![inside];
            }
            insides.push(before.first().copied());
        }
        // Each cover's inside (the side that continues the plate's top) and outside.
        for (k, sides) in covers.iter().enumerate() {
            // A cover removed has no faces.
            let Some((inside, outside)) = *sides else {
                continue;
            };
            let name = &spec.covers[k].name;
            names.insert(inside, format!("{name}.inside"));
            names.insert(outside, format!("{name}.outside"));
        }
        let twin = |f: FaceId| -> Result<FaceId, TopologyError> {
            match sheet.face_role(f)? {
                FaceRole::Side { twin } => Ok(twin),
                FaceRole::Thickness => Ok(f),
            }
        };
        for (k, (cap, walls)) in lifts.iter().enumerate() {
            let name = &spec.lifts[k].name;
            names.insert(*cap, format!("{name}.top"));
            names.insert(twin(*cap)?, format!("{name}.bottom"));
            for (i, &w) in walls.iter().enumerate() {
                names.insert(w, format!("{name}.wall_{}.top", i + 1));
                names.insert(twin(w)?, format!("{name}.wall_{}.bottom", i + 1));
            }
        }
        // Thickness faces, named after the sheet they edge (or the hole they line).
        let mut counts = std::collections::BTreeMap::<String, usize>::new();
        for f in b.faces() {
            if sheet.face_role(f)? != FaceRole::Thickness {
                continue;
            }
            let vertices = b.outer_vertices(f)?;
            let hole = hole_rings.iter().position(|ring| {
                vertices.iter().any(|&v| {
                    ring.contains(&v) || sheet.twin_vertex(v).is_ok_and(|w| ring.contains(&w))
                })
            });
            let owner = neighbours(f)?.into_iter().find_map(|side| {
                flanges
                    .iter()
                    .position(|strips| strips.iter().any(|&(a, c)| side == a || side == c))
            });
            let cover = neighbours(f)?.into_iter().find_map(|side| {
                covers
                    .iter()
                    .position(|&sides| sides.is_some_and(|(a, c)| side == a || side == c))
            });
            let prefix = match (hole, owner, cover) {
                (Some(i), ..) => format!("{}.wall", spec.holes[i].name),
                (None, Some(k), _) => format!("{}.edge", spec.flanges[k].name),
                (None, None, Some(k)) => format!("{}.edge", spec.covers[k].name),
                (None, None, None) => "plate.edge".to_string(),
            };
            let n = counts.entry(prefix.clone()).or_insert(0);
            *n += 1;
            names.insert(f, format!("{prefix}_{n}"));
        }
        // A hole or flange named `plate` could repeat a name: the later face gets its
        // id added, so every group name stays unique.
        let mut seen = std::collections::BTreeSet::new();
        for (f, name) in names.iter_mut() {
            if !seen.insert(name.clone()) {
                name.push_str(&format!("_{}", f.0));
                seen.insert(name.clone());
            }
        }
        Ok(FaceNames { names })
    }

    /// The name of face `f` (`face N` for one not named above).
    pub(super) fn of(&self, f: FaceId) -> String {
        self.names
            .get(&f)
            .cloned()
            .unwrap_or_else(|| format!("face {}", f.0))
    }
}
