//! The `round` block: a chain of sharp edges of a mesh rounded by a rolling ball at a
//! constant radius (paper 000; issue 16, under way):
//!
//! ```text
//! round shoulder {
//!     mesh = read_obj("die.obj")      // any mesh value
//!     at = (120, 40, 30)              // a point near the chain (press coordinates)
//!     radius = 8 mm
//!     angle = 30 deg                  // the feature angle θ (optional)
//!     follow = (1, 0, 0)              // which way at a branch (optional)
//!     tolerance = 0.01 mm             // the round's mesh against its arcs (optional)
//! }
//! ```
//!
//! Its pieces: `mesh` (the rounded mesh, kind `round`), `surface` (the rounding
//! surface) and the two trim lines `trim_left` and `trim_right`.

use std::sync::Arc;

use glam::DVec3;

use crate::diag::Diagnostic;
use crate::geom::curve::Curve3;
use crate::geom::mesh::rounding::base::BaseError;
use crate::geom::mesh::rounding::chain::{
    chain_through, nearest_sharp_node, sharp_edges, ChainError, DEFAULT_FEATURE_ANGLE,
};
use crate::geom::mesh::rounding::round::{round_chain, RoundError, Rounded};
use crate::geom::mesh::Topology;

use super::super::builtins::{as_angle, as_point3, type_error};
use super::super::summary::round;
use super::super::value::{Data, Record, Value};
use super::kind::{FeatureKind, FieldNames};
use super::{count, feature_error, feature_value, length, mm, Block};

/// How far (mm) the point `at` may lie from the nearest node with a sharp edge.
pub const ROUND_REACH: f64 = 5.0;

/// The tolerance the round's mesh keeps to its arcs when none is given (mm).
const DEFAULT_TOLERANCE: f64 = 0.01;

/// The `round` kind.
pub(super) static KIND: &dyn FeatureKind = &RoundKind;

struct RoundKind;

impl FeatureKind for RoundKind {
    fn name(&self) -> &'static str {
        "round"
    }
    fn code(&self) -> &'static str {
        "die::round"
    }
    fn fields(&self) -> FieldNames {
        FieldNames {
            single: vec!["mesh", "at", "radius", "angle", "follow", "tolerance"],
            named: Vec::new(),
        }
    }
    fn build(&self, block: &Block) -> Result<Value, Diagnostic> {
        build(block)
    }
    /// The rounding surface and the trim lines are pieces of their own kinds, children
    /// of the round's node beside the rounded mesh.
    fn piece_kind(&self, field: &str) -> Option<&'static str> {
        match field {
            "surface" => Some("round_surface"),
            "trim_left" | "trim_right" => Some("trim_line"),
            _ => None,
        }
    }
    fn summary(&self, record: &Record) -> String {
        let Some(r) = record.model::<Rounded>() else {
            return String::new();
        };
        format!(
            "rounded mesh, {} faces ({} in the round), {} balls along the spine",
            r.mesh.face_count(),
            r.round_faces,
            r.balls.len()
        )
    }
}

/// Builds the round of `block`.
fn build(block: &Block) -> Result<Value, Diagnostic> {
    let field = |name: &str, help: &str| {
        block
            .get(name)
            .map(|f| &f.value)
            .ok_or_else(|| block.missing(name, help))
    };
    let mesh_value = field(
        "mesh",
        "give the mesh to round: `mesh = read_obj(\"die.obj\")`",
    )?;
    let Data::Mesh(mesh) = &mesh_value.data else {
        return Err(type_error(mesh_value, "`mesh`", "a mesh"));
    };
    let at_value = field(
        "at",
        "give a point near the sharp edge to round: `at = (x, y, z)`",
    )?;
    let at = as_point3(at_value, block.units, "`at`")?;
    let radius_value = field("radius", "give the ball's radius: `radius = 8 mm`")?;
    let radius = length(radius_value, block.units, "`radius`")?;
    if !(radius.is_finite() && radius > 0.0) {
        return Err(feature_error(
            KIND,
            format!("the radius must be above 0 mm, not {radius} mm"),
            radius_value.span,
            "not a radius",
            "give the ball's radius, such as `radius = 8 mm`",
        ));
    }
    let theta = match block.get("angle") {
        Some(f) => as_angle(&f.value, block.units, "`angle`")?,
        None => DEFAULT_FEATURE_ANGLE,
    };
    let follow = match block.get("follow") {
        Some(f) => Some(as_point3(&f.value, block.units, "`follow`")?),
        None => None,
    };
    let tolerance = match block.get("tolerance") {
        Some(f) => length(&f.value, block.units, "`tolerance`")?,
        None => DEFAULT_TOLERANCE,
    };
    let mesh = mesh.triangulated();
    let topology = Topology::build(&mesh);
    let sharp = sharp_edges(&mesh, &topology, theta);
    let node = nearest_sharp_node(&mesh, &topology, &sharp, at)
        .filter(|&(_, d)| d <= ROUND_REACH)
        .ok_or_else(|| {
            feature_error(
                KIND,
                format!(
                    "no sharp edge lies within {ROUND_REACH} mm of the point: no edge there turns by \
                     more than {} deg",
                    round(theta.to_degrees())
                ),
                at_value.span,
                "this point",
                "put `at` on the sharp edge to round (within 5 mm of one of its nodes), or lower \
                 the feature `angle`",
            )
        })?;
    let chain = chain_through(&mesh, &topology, &sharp, node.0, follow).map_err(|e| {
        let place = |v: u32| show(mesh.positions()[v as usize]);
        match e {
            ChainError::Branch { node, edges } => feature_error(
                KIND,
                format!(
                    "the chain of sharp edges branches at {}, where {edges} sharp edges meet",
                    place(node)
                ),
                at_value.span,
                "the chain through this point",
                "give `follow = (x, y, z)`, the way to go on at the branch",
            ),
            ChainError::NotManifold { node } => feature_error(
                KIND,
                format!(
                    "the mesh is not manifold and consistently oriented at {}, on the chain",
                    place(node)
                ),
                mesh_value.span,
                "this mesh",
                "give a mesh whose edges along the chain each join two faces wound alike",
            ),
            ChainError::NotSharp { .. } => feature_error(
                KIND,
                e.to_string(),
                at_value.span,
                "this point",
                "put `at` on a sharp edge",
            ),
        }
    })?;
    let rounded = round_chain(&mesh, &topology, &chain, radius, tolerance).map_err(|e| {
        let (span, label, help) = match &e {
            RoundError::NoRoom { .. } => (
                radius_value.span,
                "this radius",
                "give a smaller radius: the ball must fit between the faces beside the edge",
            ),
            RoundError::Base(BaseError::NotSplit { .. }) => (
                at_value.span,
                "the chain through this point",
                "round a chain that runs to the mesh's edge or round to its start",
            ),
            _ => (
                mesh_value.span,
                "this mesh",
                "check the mesh along the chain",
            ),
        };
        feature_error(KIND, e.to_string(), span, label, help)
    })?;
    Ok(output(block, rounded))
}

/// A point as a designer reads it.
fn show(p: DVec3) -> String {
    format!("({}, {}, {})", round(p.x), round(p.y), round(p.z))
}

/// The value of a built round: its pieces and `quality`.
fn output(block: &Block, rounded: Rounded) -> Value {
    let span = block.span;
    let polyline = |points: &[DVec3]| -> Option<Curve3> {
        let n = points.len();
        if n < 2 {
            return None;
        }
        let mut knots = vec![0.0];
        knots.extend((0..n).map(|i| i as f64 / (n - 1) as f64));
        knots.push(1.0);
        Curve3::new(1, knots, points.to_vec()).ok()
    };
    let mut fields = vec![
        (
            "mesh".to_string(),
            Value::new(Data::Mesh(Arc::new(rounded.mesh.clone())), span),
        ),
        (
            "surface".to_string(),
            Value::new(Data::Surface(Arc::new(rounded.surface.clone())), span),
        ),
    ];
    for (name, line) in ["trim_left", "trim_right"].iter().zip(&rounded.trim_lines) {
        if let Some(curve) = polyline(line) {
            fields.push((
                name.to_string(),
                Value::new(Data::Curve3(Arc::new(curve)), span),
            ));
        }
    }
    let moved = rounded.balls.iter().map(|b| b.moved).fold(0.0, f64::max);
    let quality = vec![
        ("balls".to_string(), count(rounded.balls.len(), span)),
        ("round_faces".to_string(), count(rounded.round_faces, span)),
        ("recentred".to_string(), mm(moved, span)),
    ];
    feature_value(KIND, span, fields, quality, rounded)
}
