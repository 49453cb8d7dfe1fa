//! Two builds of a script compared declaration by declaration (`dieface diff`): what
//! was added, removed, renamed, changed or left as it was, and for changed geometry
//! how far the new lies from the old.
//!
//! A declaration is unchanged when its kind, its summary (`eval::summary`, numbers
//! rounded as the snapshot rounds them; not for a feature, whose summary measures every
//! patch again), its quality figures and line bead and the exact geometry of every
//! piece ([`Fingerprint`]) are the same; where it stands in the file is not
//! compared, so an edit of a comment or of whitespace changes nothing. A declaration
//! gone under one name and added under another with the same everything is a rename.
//! A changed piece is measured on its tessellations ([`crate::geom::mesh::distance`]):
//! sample points of each side to the nearest point of the other's triangles (surfaces,
//! meshes) or polylines (curves), the largest distance of both directions and where it
//! is, and the mean. Pure functions of the two builds: `cli` prints the text or JSON.

use std::collections::{HashMap, HashSet};

use glam::DVec3;
use rayon::prelude::*;
use serde_json::{json, Map, Value as Json};

use crate::die::model::{DieModel, FigureValue, LineBead, Part};
use crate::eval::summary::describe;
use crate::eval::units::round;
use crate::eval::value::Data;
use crate::eval::Outcome;
use crate::export::scene::{Geometry, Node, Scene};
use crate::geom::mesh::distance::{polylines_deviation, triangles_deviation, Deviation};
use crate::geom::mesh::rounding::index::Triangle;

use super::snapshot::coarsen;

/// The version of the `dieface diff --json` document; bumped on any change that could
/// break a reader.
pub const SCHEMA: u32 = 1;

/// One side of a comparison: a clean build's evaluation, die model and tessellation.
#[derive(Clone, Copy)]
pub struct Side<'a> {
    /// The evaluation (its declarations, in source order).
    pub outcome: &'a Outcome,
    /// Its die model.
    pub model: &'a DieModel,
    /// Its tessellation.
    pub scene: &'a Scene,
}

/// What became of one declaration.
#[derive(Debug, Clone, PartialEq)]
pub enum Status {
    /// Only in the new version.
    Added,
    /// Only in the old version.
    Removed,
    /// In both, different.
    Changed,
    /// In both, the same.
    Unchanged,
    /// The same declaration under a new name; the old name is gone.
    Renamed {
        /// Its old name.
        from: String,
    },
}

impl Status {
    /// The word for it in the text and JSON reports.
    pub fn word(&self) -> &'static str {
        match self {
            Status::Added => "added",
            Status::Removed => "removed",
            Status::Changed => "changed",
            Status::Unchanged => "unchanged",
            Status::Renamed { .. } => "renamed",
        }
    }
}

/// How one piece of a changed declaration changed.
#[derive(Debug, Clone, PartialEq)]
pub struct PieceChange {
    /// Its full name (`binder/front_nose`; the declaration's own name for its own
    /// geometry).
    pub name: String,
    /// Added, removed or changed.
    pub status: Status,
    /// For a changed piece, how far the new lies from the old (none when either side
    /// has nothing to measure, e.g. a surface that became a curve).
    pub deviation: Option<Deviation>,
}

/// A quality figure that changed: its name, the old and the new value as text.
#[derive(Debug, Clone, PartialEq)]
pub struct FigureChange {
    /// `min_radius`, `patch_a.draft`, ...
    pub name: String,
    /// The old value (`-` when the old version had no such figure).
    pub old: String,
    /// The new value (`-` when the new version has none).
    pub new: String,
}

/// One declaration of the comparison.
#[derive(Debug, Clone, PartialEq)]
pub struct Entry {
    /// Its name (the new name of a rename).
    pub name: String,
    /// Its kind (the new one when it changed).
    pub kind: String,
    /// What became of it.
    pub status: Status,
    /// The largest of its pieces' deviations (changed geometry only).
    pub deviation: Option<Deviation>,
    /// Its pieces that changed.
    pub pieces: Vec<PieceChange>,
    /// Its quality figures that changed.
    pub figures: Vec<FigureChange>,
    /// The old and the new summary, when they differ.
    pub summary: Option<(String, String)>,
}

/// The comparison of two builds.
#[derive(Debug, Clone, PartialEq)]
pub struct Comparison {
    /// Every declaration of either side: the new version's in its order (renames
    /// under the new name), then the removed ones in the old version's order.
    pub entries: Vec<Entry>,
    /// The chordal tolerance the distances were measured on (mm), the new build's.
    pub tolerance_mm: f64,
}

impl Comparison {
    /// Whether anything changed (exit 1 of `dieface diff`).
    pub fn changed(&self) -> bool {
        self.entries.iter().any(|e| e.status != Status::Unchanged)
    }
}

/// One declaration of one side, as compared.
struct Decl<'a> {
    name: &'a str,
    kind: &'a str,
    summary: String,
    /// Pieces with geometry: the name relative to the declaration (`""` for its own),
    /// the fingerprint, the tessellation.
    pieces: Vec<(String, u64, Option<&'a Node>)>,
    figures: Vec<(String, String)>,
}

impl Decl<'_> {
    /// Everything compared but the name: equal signatures are the same declaration.
    fn same_as(&self, other: &Decl) -> bool {
        self.kind == other.kind
            && self.summary == other.summary
            && self.figures == other.figures
            && self.pieces.len() == other.pieces.len()
            && self
                .pieces
                .iter()
                .zip(&other.pieces)
                .all(|(a, b)| a.0 == b.0 && a.1 == b.1)
    }
}

/// The declarations of one side, in source order.
fn decls<'a>(side: Side<'a>) -> Vec<Decl<'a>> {
    let parts: HashMap<&str, &Part> = side
        .model
        .parts
        .iter()
        .map(|p| (p.name.as_str(), p))
        .collect();
    let nodes: HashMap<&str, &Node> = side
        .scene
        .all_nodes()
        .into_iter()
        .map(|n| (n.name.as_str(), n))
        .collect();
    side.outcome
        .decls
        .iter()
        .map(|d| {
            let part = parts.get(d.name.as_str());
            let mut pieces = Vec::new();
            let mut figures = Vec::new();
            if let Some(part) = part {
                for p in part.walk() {
                    let Some(shape) = &p.shape else { continue };
                    let relative = p
                        .name
                        .strip_prefix(d.name.as_str())
                        .unwrap_or(&p.name)
                        .trim_start_matches('/')
                        .to_string();
                    pieces.push((
                        relative,
                        shape.fingerprint(),
                        nodes.get(p.name.as_str()).copied(),
                    ));
                }
                figures = part
                    .figures
                    .iter()
                    .map(|f| (f.name.clone(), figure_text(&f.value)))
                    .collect();
                for p in part.walk() {
                    if let Some(bead) = &p.line_bead {
                        // Named within the declaration, so a rename keeps them.
                        let relative = p.name.strip_prefix(d.name.as_str()).unwrap_or(&p.name);
                        figures.extend(line_bead_figures(relative.trim_start_matches('/'), bead));
                    }
                }
            }
            // A feature is told by its pieces, figures and line bead; its summary (the
            // area and bounds of every patch) would cost more than the whole build.
            let is_feature = d
                .value
                .as_ref()
                .is_some_and(|v| matches!(&v.data, Data::Record(r) if r.feature.is_some()));
            Decl {
                name: &d.name,
                kind: &d.kind,
                summary: if is_feature {
                    String::new()
                } else {
                    coarsen(&describe(d.value.as_ref()))
                },
                pieces,
                figures,
            }
        })
        .collect()
}

/// A line bead as figures: its restraining force, spacing and point count (its points
/// move with the bead's pieces, which are measured).
fn line_bead_figures(piece: &str, bead: &LineBead) -> Vec<(String, String)> {
    let name = if piece.is_empty() {
        "line_bead".to_string()
    } else {
        format!("{piece}.line_bead")
    };
    let force = bead
        .force
        .map_or("-".to_string(), |f| coarsen(&format!("{} N/mm", round(f))));
    vec![
        (format!("{name}.force"), force),
        (
            format!("{name}.spacing"),
            coarsen(&format!("{} mm", round(bead.spacing))),
        ),
        (format!("{name}.points"), bead.points.len().to_string()),
    ]
}

/// A quality figure as text, rounded as the snapshot rounds it.
fn figure_text(v: &FigureValue) -> String {
    let text = match v {
        FigureValue::Length(x) => format!("{} mm", round(*x)),
        FigureValue::Angle(x) => format!("{} deg", round(*x)),
        FigureValue::Number(x) => format!("{}", round(*x)),
        FigureValue::Point(p) => format!("({}, {}, {}) mm", round(p.x), round(p.y), round(p.z)),
        FigureValue::Flag(b) => if *b { "yes" } else { "no" }.to_string(),
    };
    coarsen(&text)
}

/// Compares the old and the new build.
pub fn compare(old: Side, new: Side) -> Comparison {
    let old_decls = decls(old);
    let new_decls = decls(new);
    let old_by_name: HashMap<&str, &Decl> = old_decls.iter().map(|d| (d.name, d)).collect();
    let new_names: HashSet<&str> = new_decls.iter().map(|d| d.name).collect();
    // Renames: a declaration only in the new version that matches one only in the old
    // version in everything but its name (the first such, in the old version's order).
    let mut renamed_from: HashMap<&str, &str> = HashMap::new();
    let mut taken: HashSet<&str> = HashSet::new();
    for d in new_decls
        .iter()
        .filter(|d| !old_by_name.contains_key(d.name))
    {
        let found = old_decls
            .iter()
            .find(|o| !new_names.contains(o.name) && !taken.contains(o.name) && o.same_as(d));
        if let Some(o) = found {
            taken.insert(o.name);
            renamed_from.insert(d.name, o.name);
        }
    }
    let mut entries: Vec<Entry> = new_decls
        .par_iter()
        .map(
            |d| match (old_by_name.get(d.name), renamed_from.get(d.name)) {
                (_, Some(from)) => plain(
                    d,
                    Status::Renamed {
                        from: from.to_string(),
                    },
                ),
                (None, None) => plain(d, Status::Added),
                (Some(o), None) if o.same_as(d) => plain(d, Status::Unchanged),
                (Some(o), None) => changed(o, d),
            },
        )
        .collect();
    entries.extend(
        old_decls
            .iter()
            .filter(|o| !new_names.contains(o.name) && !taken.contains(o.name))
            .map(|o| plain(o, Status::Removed)),
    );
    Comparison {
        entries,
        tolerance_mm: new.scene.tolerance_mm,
    }
}

/// An entry with nothing more to say than its status.
fn plain(d: &Decl, status: Status) -> Entry {
    Entry {
        name: d.name.to_string(),
        kind: d.kind.to_string(),
        status,
        deviation: None,
        pieces: Vec::new(),
        figures: Vec::new(),
        summary: None,
    }
}

/// The entry of a declaration in both versions that differs: its pieces measured, its
/// figures and summary compared.
fn changed(old: &Decl, new: &Decl) -> Entry {
    let old_pieces: HashMap<&str, &(String, u64, Option<&Node>)> =
        old.pieces.iter().map(|p| (p.0.as_str(), p)).collect();
    let new_names: HashSet<&str> = new.pieces.iter().map(|p| p.0.as_str()).collect();
    let full = |relative: &str| {
        if relative.is_empty() {
            new.name.to_string()
        } else {
            format!("{}/{relative}", new.name)
        }
    };
    let mut pieces: Vec<PieceChange> = Vec::new();
    for p in &new.pieces {
        match old_pieces.get(p.0.as_str()) {
            None => pieces.push(PieceChange {
                name: full(&p.0),
                status: Status::Added,
                deviation: None,
            }),
            Some(o) if o.1 == p.1 => {}
            Some(o) => pieces.push(PieceChange {
                name: full(&p.0),
                status: Status::Changed,
                deviation: match (o.2, p.2) {
                    (Some(a), Some(b)) => node_deviation(a, b),
                    _ => None,
                },
            }),
        }
    }
    for o in old
        .pieces
        .iter()
        .filter(|o| !new_names.contains(o.0.as_str()))
    {
        pieces.push(PieceChange {
            name: full(&o.0),
            status: Status::Removed,
            deviation: None,
        });
    }
    let deviation =
        pieces
            .iter()
            .filter_map(|p| p.deviation)
            .reduce(|a, b| if b.max > a.max { b } else { a });
    let old_figures: HashMap<&str, &str> = old
        .figures
        .iter()
        .map(|(n, v)| (n.as_str(), v.as_str()))
        .collect();
    let new_figure_names: HashSet<&str> = new.figures.iter().map(|f| f.0.as_str()).collect();
    let mut figures: Vec<FigureChange> = new
        .figures
        .iter()
        .filter(|(n, v)| old_figures.get(n.as_str()) != Some(&v.as_str()))
        .map(|(n, v)| FigureChange {
            name: n.clone(),
            old: old_figures
                .get(n.as_str())
                .map_or("-".into(), |s| s.to_string()),
            new: v.clone(),
        })
        .collect();
    figures.extend(
        old.figures
            .iter()
            .filter(|(n, _)| !new_figure_names.contains(n.as_str()))
            .map(|(n, v)| FigureChange {
                name: n.clone(),
                old: v.clone(),
                new: "-".into(),
            }),
    );
    // The summary is told only where no piece or figure already says what changed.
    let summary = (old.summary != new.summary && pieces.is_empty() && figures.is_empty())
        .then(|| (old.summary.clone(), new.summary.clone()));
    Entry {
        name: new.name.to_string(),
        kind: new.kind.to_string(),
        status: Status::Changed,
        deviation,
        pieces,
        figures,
        summary,
    }
}

/// How far one tessellated piece lies from another: triangles against triangles and
/// polylines against polylines, the larger of the two.
fn node_deviation(old: &Node, new: &Node) -> Option<Deviation> {
    let (old_t, old_l) = primitives(old);
    let (new_t, new_l) = primitives(new);
    let t = triangles_deviation(&old_t, &new_t);
    let l = polylines_deviation(&old_l, &new_l);
    match (t, l) {
        (Some(a), Some(b)) => Some(if b.max > a.max {
            b.merge(a)
        } else {
            a.merge(b)
        }),
        (a, b) => a.or(b),
    }
}

/// A node's own triangles and polylines.
fn primitives(node: &Node) -> (Vec<Triangle>, Vec<Vec<DVec3>>) {
    let lines = node
        .geometry
        .iter()
        .filter_map(|g| match g.as_ref() {
            Geometry::LineStrip { points } => Some(points.clone()),
            Geometry::Triangles { .. } => None,
        })
        .collect();
    (node.triangles(), lines)
}

/// A distance as reported: rounded to 0.001 mm.
pub fn mm(v: f64) -> f64 {
    let r = (v * 1e3).round() / 1e3;
    if r == 0.0 {
        0.0
    } else {
        r
    }
}

/// A deviation as text: `largest 5.002 mm at (1.2, -3, 4), mean 3.1 mm`.
fn deviation_text(d: &Deviation) -> String {
    format!(
        "largest {} mm at ({}, {}, {}), mean {} mm",
        mm(d.max),
        mm(d.at.x),
        mm(d.at.y),
        mm(d.at.z),
        mm(d.mean)
    )
}

/// The text report: one block per declaration that is not unchanged, then the counts
/// (or `no change (N declarations)`).
pub fn text_report(c: &Comparison) -> Vec<String> {
    let mut out = Vec::new();
    for e in c.entries.iter().filter(|e| e.status != Status::Unchanged) {
        let head = format!("{:<8} {} {}", e.status.word(), e.kind, e.name);
        match &e.status {
            Status::Renamed { from } => {
                out.push(format!("renamed  {} {from} -> {}", e.kind, e.name))
            }
            Status::Changed => {
                out.push(match &e.deviation {
                    Some(d) => format!("{head}: {}", deviation_text(d)),
                    None => head,
                });
                for p in &e.pieces {
                    let what = match (&p.status, &p.deviation) {
                        (Status::Changed, Some(d)) => deviation_text(d),
                        (Status::Changed, None) => "changed (nothing to measure)".into(),
                        (s, _) => s.word().to_string(),
                    };
                    out.push(format!("    {}: {what}", p.name));
                }
                for f in &e.figures {
                    out.push(format!("    quality {}: {} -> {}", f.name, f.old, f.new));
                }
                if let Some((a, b)) = &e.summary {
                    out.push(format!("    was: {a}"));
                    out.push(format!("    now: {b}"));
                }
            }
            _ => out.push(head),
        }
    }
    let count = |w: &str| c.entries.iter().filter(|e| e.status.word() == w).count();
    if c.changed() {
        let mut parts = Vec::new();
        for w in ["changed", "renamed", "added", "removed", "unchanged"] {
            let n = count(w);
            if n > 0 {
                parts.push(format!("{n} {w}"));
            }
        }
        out.push(format!(
            "{} (distances on tessellations within {} mm)",
            parts.join(", "),
            c.tolerance_mm
        ));
    } else {
        out.push(format!("no change ({} declarations)", c.entries.len()));
    }
    out
}

/// A deviation as JSON: `max_mm`, `at` (x, y, z in mm), `mean_mm`, `samples`.
fn deviation_json(d: &Deviation) -> Json {
    json!({
        "max_mm": mm(d.max),
        "at": [mm(d.at.x), mm(d.at.y), mm(d.at.z)],
        "mean_mm": mm(d.mean),
        "samples": d.samples,
    })
}

/// The JSON report (schema [`SCHEMA`]): `old`, `new` (the two versions' labels),
/// `changed`, `tolerance_mm`, and `declarations`, each with `name`, `kind`, `status`,
/// and as they apply `renamed_from`, `deviation`, `pieces`, `figures`, `summary`.
/// Distances are rounded to 0.001 mm, as in the text.
pub fn json_report(c: &Comparison, old: &str, new: &str) -> Json {
    let decls: Vec<Json> = c
        .entries
        .iter()
        .map(|e| {
            let mut m = Map::new();
            m.insert("name".into(), json!(e.name));
            m.insert("kind".into(), json!(e.kind));
            m.insert("status".into(), json!(e.status.word()));
            if let Status::Renamed { from } = &e.status {
                m.insert("renamed_from".into(), json!(from));
            }
            if let Some(d) = &e.deviation {
                m.insert("deviation".into(), deviation_json(d));
            }
            if !e.pieces.is_empty() {
                let pieces: Vec<Json> = e
                    .pieces
                    .iter()
                    .map(|p| {
                        let mut pm = Map::new();
                        pm.insert("name".into(), json!(p.name));
                        pm.insert("status".into(), json!(p.status.word()));
                        if let Some(d) = &p.deviation {
                            pm.insert("deviation".into(), deviation_json(d));
                        }
                        Json::Object(pm)
                    })
                    .collect();
                m.insert("pieces".into(), Json::Array(pieces));
            }
            if !e.figures.is_empty() {
                let figures: Vec<Json> = e
                    .figures
                    .iter()
                    .map(|f| json!({"name": f.name, "old": f.old, "new": f.new}))
                    .collect();
                m.insert("figures".into(), Json::Array(figures));
            }
            if let Some((a, b)) = &e.summary {
                m.insert("summary".into(), json!({"old": a, "new": b}));
            }
            Json::Object(m)
        })
        .collect();
    let mut top = Map::new();
    top.insert("schema".into(), json!(SCHEMA));
    top.insert("old".into(), json!(old));
    top.insert("new".into(), json!(new));
    top.insert("changed".into(), json!(c.changed()));
    top.insert("tolerance_mm".into(), json!(c.tolerance_mm));
    top.insert("declarations".into(), Json::Array(decls));
    Json::Object(top)
}
