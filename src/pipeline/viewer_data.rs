//! What the live viewer's page reads besides the GLB (`dieface view`, `watch --serve`):
//! the declarations with their lines, summaries and quality figures (the same text as
//! `inspect`), one picked piece's summary, and the normal jump along the seams. Pure
//! functions returning JSON; `cli` serves them.
//!
//! Positions sent to the page are in the GLB's frame (glTF metres, +Y up), so the page
//! draws them beside the model without converting.

use serde_json::{json, Value as Json};

use crate::diag::Sources;
use crate::die::model::Part;
use crate::eval::summary::feature_report;
use crate::eval::Outcome;
use crate::export::gltf::to_gltf_position;
use crate::export::scene::Scene;
use crate::export::seams::seam_points;

/// The page's model description: the script, the tolerance, and per declaration its
/// kind, name, line and quality report lines. Made at every save, so it holds only
/// what is already computed: a summary (bounds and areas are sampled) is asked for one
/// piece at a time ([`piece_info`]).
pub fn model_info(outcome: &Outcome, sources: &Sources, scene: &Scene) -> Json {
    let declarations: Vec<Json> = outcome
        .decls
        .iter()
        .map(|d| {
            json!({
                "name": d.name,
                "kind": d.kind,
                "line": sources.line(d.span),
                "figures": d.value.as_ref().map(feature_report).unwrap_or_default(),
            })
        })
        .collect();
    json!({
        "source": scene.source_name,
        "tolerance_mm": scene.tolerance_mm,
        "declarations": declarations,
    })
}

/// One piece of the die model's parts by its full name (`binder/front_nose`): its
/// kind, line and shape summary (as `dieface snapshot` writes it), or `None` when there
/// is no such piece.
pub fn piece_info(parts: &[Part], name: &str) -> Option<Json> {
    let piece = parts
        .iter()
        .flat_map(|p| p.walk())
        .find(|p| p.name == name)?;
    Some(json!({
        "name": piece.name,
        "kind": piece.kind,
        "line": piece.line,
        "summary": super::snapshot::piece_summary(piece),
    }))
}

/// The normal jump along the scene's seams (`export::seams`), for the page's analysis
/// mode: the gap within which two open edges count as one seam (mm), the largest jump,
/// and the points as flat arrays (`positions` in glTF metres, three numbers a point;
/// `jumps` in degrees; `pieces` the pair of piece names per point as indexes into
/// `names`).
pub fn seams_info(scene: &Scene) -> Json {
    // A seam's two sides are tessellated each to the tolerance, so a vertex of one can
    // lie up to about the tolerance off the other's chords.
    let gap = (scene.tolerance_mm * 2.0).max(0.01);
    let points = seam_points(scene, gap);
    let mut names: Vec<String> = Vec::new();
    let mut index = |n: &str| match names.iter().position(|m| m == n) {
        Some(i) => i,
        None => {
            names.push(n.to_string());
            names.len() - 1
        }
    };
    let mut positions = Vec::with_capacity(points.len() * 3);
    let mut jumps = Vec::with_capacity(points.len());
    let mut pieces = Vec::with_capacity(points.len() * 2);
    let mut worst: Option<&crate::export::seams::SeamPoint> = None;
    for p in &points {
        positions.extend(to_gltf_position(p.at).map(f64::from));
        jumps.push((p.jump_deg * 1e4).round() / 1e4);
        pieces.push(index(&p.piece));
        pieces.push(index(&p.other));
        if worst.is_none_or(|w| p.jump_deg > w.jump_deg) {
            worst = Some(p);
        }
    }
    json!({
        "gap_mm": gap,
        "count": points.len(),
        "max_deg": worst.map_or(0.0, |w| w.jump_deg),
        "max_at_mm": worst.map(|w| [w.at.x, w.at.y, w.at.z]),
        "max_between": worst.map(|w| [w.piece.clone(), w.other.clone()]),
        "names": names,
        "positions": positions,
        "jumps": jumps,
        "pieces": pieces,
    })
}
