//! The `fill` block (paper 002; issue 17): a mesh's holes filled from smooth base
//! surfaces, its cracks stitched first, its outer boundary kept.
//!
//! ```text
//! fill closed {
//!     mesh = read_obj("inner.obj")    // any mesh value
//!     holes = "all"                   // or a size: those up to 40 mm across (`40 mm`),
//!                                     // or points: the hole nearest each
//!     outer = (0, -300, 0)            // the panel's outer boundary is the loop nearest
//!                                     // this point (optional: found otherwise)
//!     stitch = 0.05 mm                // cracks narrower than this closed first (optional)
//!     size = 5 mm                     // element size inside the fills (optional: the
//!                                     // loop's own edges)
//! }
//! ```
//!
//! The mesh's own faces are kept, quads as quads (an FE mesh's elements and their
//! numbers are the engineer's); the fills are triangles. Its pieces: `mesh` (the filled
//! mesh, kind `fill`), and for each hole filled
//! `patch_K` (the fill's own triangles, `fill_patch`) and `base_K` (its base surface,
//! `fill_base`), children of the block's node, so a reviewer sees what was added.

use std::sync::Arc;

use glam::DVec3;

use crate::diag::Diagnostic;
use crate::geom::mesh::holes::cracks::stitch_cracks;
use crate::geom::mesh::holes::loops::LoopProblem;
use crate::geom::mesh::holes::{
    fill_holes, fill_holes_in, FillOptions, Filled, FilledHole, HoleChoice, HoleError,
};

use super::super::builtins::{as_point3, type_error};
use super::super::summary::round;
use super::super::value::{Data, Record, Value};
use super::kind::{FeatureKind, FieldNames};
use super::{count, deg, feature_error, feature_value, items, length, mm, Block};

/// The `fill` kind.
pub(super) static KIND: &dyn FeatureKind = &FillKind;

struct FillKind;

/// What a fill block did, as `inspect` summarises it (the meshes themselves are the
/// record's fields).
#[derive(Debug, Clone)]
pub struct FillSummary {
    /// Faces of the filled mesh.
    pub faces: usize,
    /// Faces the fills added.
    pub fill_faces: usize,
    /// Holes filled.
    pub holes: usize,
    /// Free loops before filling (after stitching).
    pub loops_before: usize,
}

impl FeatureKind for FillKind {
    fn name(&self) -> &'static str {
        "fill"
    }
    fn code(&self) -> &'static str {
        "die::fill"
    }
    fn fields(&self) -> FieldNames {
        FieldNames {
            single: vec!["mesh", "holes", "outer", "stitch", "size"],
            named: Vec::new(),
        }
    }
    fn build(&self, block: &Block) -> Result<Value, Diagnostic> {
        build_fill(block)
    }
    fn piece_kind(&self, field: &str) -> Option<&'static str> {
        match field {
            "mesh" => Some("fill"),
            f if f.starts_with("patch_") => Some("fill_patch"),
            f if f.starts_with("base_") => Some("fill_base"),
            _ => None,
        }
    }
    fn summary(&self, record: &Record) -> String {
        let Some(m) = record.model::<FillSummary>() else {
            return String::new();
        };
        format!(
            "filled mesh, {} faces ({} in {} fills), {} free loops before",
            m.faces, m.fill_faces, m.holes, m.loops_before
        )
    }
}

/// A positive length in field `name`, or `None` when the field is absent.
fn positive(block: &Block, name: &str, help: &str) -> Result<Option<f64>, Diagnostic> {
    let Some(f) = block.get(name) else {
        return Ok(None);
    };
    let v = length(&f.value, block.units, &format!("`{name}`"))?;
    if !(v.is_finite() && v > 0.0) {
        return Err(feature_error(
            KIND,
            format!("`{name}` must be above 0 mm, not {} mm", round(v)),
            f.value.span,
            "not a length above 0",
            help,
        ));
    }
    Ok(Some(v))
}

/// Which holes the `holes` field chooses.
fn choice(block: &Block) -> Result<HoleChoice, Diagnostic> {
    let Some(f) = block.get("holes") else {
        return Ok(HoleChoice::All);
    };
    let help = "give `holes = \"all\"`, a size (`holes = 40 mm`: those up to 40 mm across), \
                or points (`holes = [(x, y, z), ...]`: the hole nearest each)";
    match &f.value.data {
        Data::Str(s) if &**s == "all" => Ok(HoleChoice::All),
        Data::Str(s) => Err(feature_error(
            KIND,
            format!("`holes` takes the word \"all\", not \"{s}\""),
            f.value.span,
            "not a choice of holes",
            help,
        )),
        Data::Number(_) => {
            Ok(positive(block, "holes", help)?.map_or(HoleChoice::All, HoleChoice::UpTo))
        }
        Data::List(_) | Data::Tuple(_) => {
            let points = if matches!(f.value.data, Data::Tuple(_)) {
                vec![f.value.clone()]
            } else {
                items(&f.value)
            };
            let mut at = Vec::with_capacity(points.len());
            for p in &points {
                at.push(as_point3(p, block.units, "a hole's point")?);
            }
            Ok(HoleChoice::At(at))
        }
        _ => Err(type_error(
            &f.value,
            "`holes`",
            "\"all\", a size or a list of points",
        )),
    }
}

/// Builds the block.
fn build_fill(block: &Block) -> Result<Value, Diagnostic> {
    let mesh_field = block.get("mesh").ok_or_else(|| {
        block.missing(
            "mesh",
            "give the mesh to fill: `mesh = read_obj(\"inner.obj\")`",
        )
    })?;
    let mesh = match &mesh_field.value.data {
        Data::Mesh(mesh) => mesh,
        Data::Str(file) => {
            return Err(feature_error(
                KIND,
                format!("`mesh` must be a mesh, not the file name \"{file}\""),
                mesh_field.value.span,
                "a file name",
                format!("read the mesh from the file: `mesh = read_obj(\"{file}\")`"),
            ))
        }
        _ => return Err(type_error(&mesh_field.value, "`mesh`", "a mesh")),
    };
    let holes = choice(block)?;
    let outer = match block.get("outer") {
        Some(f) => Some(as_point3(&f.value, block.units, "`outer`")?),
        None => None,
    };
    let stitch = positive(
        block,
        "stitch",
        "give the widest crack to close, such as `stitch = 0.05 mm`",
    )?;
    let size = positive(
        block,
        "size",
        "give the element size inside the fills, such as `size = 5 mm`",
    )?;
    // The mesh's own faces are kept as they are, quads too: the fills add triangles on
    // the loops' nodes, and stitching splits only the faces a crack's nodes fall on.
    let (stitched_mesh, stitched) = match stitch {
        Some(t) => {
            let (m, s) = stitch_cracks(mesh, t).map_err(|e| {
                feature_error(
                    KIND,
                    format!("the cracks could not be stitched: {e}"),
                    block.get("stitch").map_or(block.head(), |f| f.value.span),
                    "this tolerance",
                    "give a smaller tolerance than the mesh's shortest edges",
                )
            })?;
            (Some(m), (s.merged_nodes, s.split_edges))
        }
        None => (None, (0, 0)),
    };
    let options = FillOptions { holes, outer, size };
    // A stitched mesh is this block's own and is filled in place; the mesh handed in
    // is shared, and is filled as a copy.
    let filled = match stitched_mesh {
        Some(stitched_mesh) => fill_holes_in(stitched_mesh, &options),
        None => fill_holes(mesh, &options),
    }
    .map_err(|e| hole_error(block, &mesh_field.value, e))?;
    Ok(output(block, filled, stitched))
}

/// A point as a designer reads it.
fn show(p: DVec3) -> String {
    format!("({}, {}, {})", round(p.x), round(p.y), round(p.z))
}

/// A kernel refusal, at the field it is about; it names the hole by where it is.
fn hole_error(block: &Block, mesh_value: &Value, e: HoleError) -> Diagnostic {
    let holes_span = block.get("holes").map_or(mesh_value.span, |f| f.value.span);
    match e {
        HoleError::NoHole => feature_error(
            KIND,
            "the mesh has no hole to fill: no loop of free edges",
            holes_span,
            "no hole near here",
            "check the mesh's free edges with `free_edges(mesh)`",
        ),
        HoleError::NothingNear { point, distance } => feature_error(
            KIND,
            format!(
                "no hole near {}: the nearest hole's rim is {} mm away, farther than the hole is across",
                show(point),
                round(distance)
            ),
            holes_span,
            "this point picks no hole",
            "pick a point inside the hole or on its rim; `free_edges(mesh)` lists where \
             each loop is (`at`)",
        ),
        HoleError::Loop {
            centre, problem, ..
        } => {
            let (what, help) = match problem {
                LoopProblem::Degenerate(why) => (
                    format!("the hole at {} is degenerate: {why}", show(centre)),
                    "a loop with no area is a crack or a T-junction: close it with `stitch`, \
                     or repair the mesh there",
                ),
                LoopProblem::NotManifold { at, .. } => (
                    format!(
                        "the hole at {} has an edge joining more than two faces at its node {}",
                        show(centre),
                        show(at)
                    ),
                    "repair the mesh round the hole so each edge joins at most two faces",
                ),
                LoopProblem::Inconsistent { at, .. } => (
                    format!(
                        "the faces round the hole at {} are not wound alike at its node {}",
                        show(centre),
                        show(at)
                    ),
                    "turn the faces round the hole so they face the same side",
                ),
                LoopProblem::Open => (
                    format!(
                        "the free edges round the hole at {} do not close a loop",
                        show(centre)
                    ),
                    "check the faces round the hole: each edge joins at most two faces, \
                     wound alike",
                ),
            };
            feature_error(KIND, what, mesh_value.span, "this mesh", help)
        }
        HoleError::NotSingleValued { centre, reason, .. } => feature_error(
            KIND,
            format!(
                "the hole at {} cannot be filled without folding: {reason}",
                show(centre)
            ),
            holes_span,
            "the holes to fill",
            "leave this hole out (`holes` by points or by size), or split it at the sharp \
             feature it wraps round",
        ),
        HoleError::Base {
            centre, problem, ..
        } => feature_error(
            KIND,
            format!(
                "the hole at {} has no base surface: {problem}",
                show(centre)
            ),
            mesh_value.span,
            "this mesh",
            "check the mesh round the hole",
        ),
        HoleError::Mesh(why) => feature_error(
            KIND,
            format!("the filled mesh could not be made: {why}"),
            mesh_value.span,
            "this mesh",
            "fill fewer holes at once, or give a larger `size` inside the fills",
        ),
    }
}

/// The block's value: the filled mesh, each fill and its base surface (moved into the
/// record, not copied), and `quality`; `stitched` is the nodes merged and edges split
/// closing cracks first.
fn output(block: &Block, f: Filled, stitched: (usize, usize)) -> Value {
    let span = block.span;
    let fill_faces: usize = f.holes.iter().map(|h| h.patch.face_count()).sum();
    let worst = |g: &dyn Fn(&FilledHole) -> f64, start: f64, max: bool| {
        f.holes
            .iter()
            .map(g)
            .fold(start, |a, b| if max { a.max(b) } else { a.min(b) })
    };
    let quality = vec![
        ("holes_filled".to_string(), count(f.holes.len(), span)),
        ("fill_faces".to_string(), count(fill_faces, span)),
        (
            "free_loops_before".to_string(),
            count(f.free.loops.len(), span),
        ),
        (
            "free_loops_after".to_string(),
            count(f.free.loops.len() - f.holes.len(), span),
        ),
        ("cracks_merged".to_string(), count(stitched.0, span)),
        ("cracks_split".to_string(), count(stitched.1, span)),
        (
            "rim_gap".to_string(),
            mm(worst(&|h| h.rim_gap, 0.0, true), span),
        ),
        (
            "normal_jump".to_string(),
            deg(worst(&|h| h.normal_jump, 0.0, true), span),
        ),
        (
            "min_angle".to_string(),
            deg(worst(&|h| h.min_angle, 180.0, false), span),
        ),
    ];
    let summary = FillSummary {
        faces: f.mesh.face_count(),
        fill_faces,
        holes: f.holes.len(),
        loops_before: f.free.loops.len(),
    };
    let mut fields = vec![(
        "mesh".to_string(),
        Value::new(Data::Mesh(Arc::new(f.mesh)), span),
    )];
    for (k, hole) in f.holes.into_iter().enumerate() {
        fields.push((
            format!("patch_{}", k + 1),
            Value::new(Data::Mesh(Arc::new(hole.patch)), span),
        ));
        fields.push((
            format!("base_{}", k + 1),
            Value::new(Data::Surface(Arc::new(hole.base.surface())), span),
        ));
    }
    feature_value(KIND, span, fields, quality, summary)
}
