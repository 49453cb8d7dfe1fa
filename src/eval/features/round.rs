//! The `round` and `reround` blocks (paper 000; issue 16, under way): a chain of sharp
//! edges of a mesh rounded by a rolling ball, and a round the mesh already has found by
//! its curvature and rounded again at a new radius:
//!
//! ```text
//! round shoulder {
//!     mesh = read_obj("die.obj")      // any mesh value
//!     at = (120, 40, 30)              // a point near the chain (press coordinates)
//!     radius = 8 mm                   // or radii along the chain, below
//!     angle = 30 deg                  // the feature angle θ (optional)
//!     follow = (1, 0, 0)              // which way at a branch (optional)
//!     tolerance = 0.01 mm             // the round's mesh against its arcs (optional)
//! }
//!
//! reround wider {
//!     mesh = shoulder.mesh
//!     at = (120, 40, 27)              // a point on the round to change
//!     radius = [{ at: (0, 40, 27), radius: 7.5 mm },
//!               { at: (150, 40, 27), radius: 15 mm },
//!               { at: (300, 40, 27), radius: 7.5 mm }]
//!     band = 0.25                     // how alike the round's curvature is (optional)
//! }
//! ```
//!
//! A list of radii, each at a point near the chain (or round), varies the radius along
//! it by a cubic spline in arc length. Their pieces: `mesh` (the rounded mesh, kind
//! `round`), `surface` (the rounding surface) and the two trim lines `trim_left` and
//! `trim_right`.

use std::sync::Arc;

use glam::DVec3;

use crate::diag::Diagnostic;
use crate::geom::curve::Curve3;
use crate::geom::mesh::curvature::CurvatureAt;
use crate::geom::mesh::rounding::base::BaseError;
use crate::geom::mesh::rounding::chain::{
    chain_through, nearest_sharp_node, sharp_edges, ChainError, DEFAULT_FEATURE_ANGLE,
};
use crate::geom::mesh::rounding::existing::{
    find_round, reround_site, ExistingRound, FindError, DEFAULT_BAND,
};
use crate::geom::mesh::rounding::radius::{RadiusError, RadiusLaw};
use crate::geom::mesh::rounding::round::{
    polyline_length, round_chain, round_site, RoundError, Rounded,
};
use crate::geom::mesh::rounding::{chain_polyline, polyline_nearest};
use crate::geom::mesh::{Mesh, Topology, VertexId};
use crate::syntax::Span;

use super::super::builtins::{as_angle, as_number, as_point3, type_error};
use super::super::summary::round;
use super::super::units::Units;
use super::super::value::{Data, Record, Value};
use super::kind::{FeatureKind, FieldNames};
use super::{count, feature_error, feature_value, length, mm, Block};

/// How far (mm) the point `at` may lie from the nearest node with a sharp edge (or, for
/// `reround`, from the nearest node).
pub const ROUND_REACH: f64 = 5.0;

/// The tolerance the round's mesh keeps to its arcs when none is given (mm).
const DEFAULT_TOLERANCE: f64 = 0.01;

/// The `round` kind.
pub(super) static KIND: &dyn FeatureKind = &RoundKind;

/// The `reround` kind.
pub(super) static REROUND: &dyn FeatureKind = &ReroundKind;

struct RoundKind;

struct ReroundKind;

/// The rounding surface and the trim lines are pieces of their own kinds, children of
/// the round's node beside the rounded mesh.
fn round_piece_kind(field: &str) -> Option<&'static str> {
    match field {
        "surface" => Some("round_surface"),
        "trim_left" | "trim_right" => Some("trim_line"),
        _ => None,
    }
}

/// One line on a built round.
fn round_summary(record: &Record) -> String {
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
        build_round(block)
    }
    fn piece_kind(&self, field: &str) -> Option<&'static str> {
        round_piece_kind(field)
    }
    fn summary(&self, record: &Record) -> String {
        round_summary(record)
    }
}

impl FeatureKind for ReroundKind {
    fn name(&self) -> &'static str {
        "reround"
    }
    fn code(&self) -> &'static str {
        "die::reround"
    }
    fn fields(&self) -> FieldNames {
        FieldNames {
            single: vec!["mesh", "at", "radius", "band", "tolerance"],
            named: Vec::new(),
        }
    }
    fn build(&self, block: &Block) -> Result<Value, Diagnostic> {
        build_reround(block)
    }
    fn piece_kind(&self, field: &str) -> Option<&'static str> {
        round_piece_kind(field)
    }
    fn summary(&self, record: &Record) -> String {
        let Some(r) = record.model::<Rounded>() else {
            return String::new();
        };
        format!(
            "re-rounded mesh, {} faces ({} in the round), {} balls along the spine",
            r.mesh.face_count(),
            r.round_faces,
            r.balls.len()
        )
    }
}

/// What both blocks read the same way: the mesh (triangulated), the point, the radius
/// field and the tolerance.
struct Common<'a> {
    mesh_value: &'a Value,
    mesh: Mesh,
    topology: Topology,
    at_value: &'a Value,
    at: DVec3,
    radius_value: &'a Value,
    tolerance: f64,
}

/// Reads the fields both blocks share, for `kind`.
fn common<'a>(kind: &'static dyn FeatureKind, block: &'a Block) -> Result<Common<'a>, Diagnostic> {
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
    let at_help = if kind.name() == "round" {
        "give a point near the sharp edge to round: `at = (x, y, z)`"
    } else {
        "give a point on the round to change: `at = (x, y, z)`"
    };
    let at_value = field("at", at_help)?;
    let at = as_point3(at_value, block.units, "`at`")?;
    let radius_value = field(
        "radius",
        "give the ball's radius, `radius = 8 mm`, or radii along the edge, \
         `radius = [{ at: (x, y, z), radius: 8 mm }, ...]`",
    )?;
    let tolerance = match block.get("tolerance") {
        Some(f) => {
            let t = length(&f.value, block.units, "`tolerance`")?;
            if !(t.is_finite() && t > 0.0) {
                return Err(feature_error(
                    kind,
                    format!("the tolerance must be above 0 mm, not {} mm", round(t)),
                    f.value.span,
                    "not a tolerance",
                    "give how near the round's mesh keeps to its arcs, such as `tolerance = 0.01 mm`",
                ));
            }
            t
        }
        None => DEFAULT_TOLERANCE,
    };
    let mesh = mesh.triangulated();
    let topology = Topology::build(&mesh);
    Ok(Common {
        mesh_value,
        mesh,
        topology,
        at_value,
        at,
        radius_value,
        tolerance,
    })
}

/// The radius of `value` along `guide` (a polyline, closed or not): one length, or a
/// list of `{ at: point, radius: length }`, each point placed at the arc length of its
/// nearest point on the guide.
fn radius_law(
    kind: &'static dyn FeatureKind,
    value: &Value,
    units: Units,
    guide: &[DVec3],
    closed: bool,
) -> Result<RadiusLaw, Diagnostic> {
    let not_positive = |r: f64, span: Span| {
        feature_error(
            kind,
            format!("a radius must be above 0 mm, not {} mm", round(r)),
            span,
            "not a radius",
            "give the ball's radius, such as `radius = 8 mm`",
        )
    };
    let total = polyline_length(guide);
    let list = match &value.data {
        Data::List(items) => items,
        _ => {
            let r = length(value, units, "`radius`")?;
            if !(r.is_finite() && r > 0.0) {
                return Err(not_positive(r, value.span));
            }
            return Ok(RadiusLaw::constant(r));
        }
    };
    let expected = "a radius at a point, `{ at: (x, y, z), radius: 8 mm }`";
    let mut given = Vec::with_capacity(list.len());
    let mut spans = Vec::with_capacity(list.len());
    for item in list.iter() {
        let Data::Record(record) = &item.data else {
            return Err(type_error(item, "an item of `radius`", expected));
        };
        let (Some(at), Some(r)) = (record.get("at"), record.get("radius")) else {
            return Err(type_error(item, "an item of `radius`", expected));
        };
        let point = as_point3(at, units, "`at`")?;
        let r_mm = length(r, units, "`radius`")?;
        if !(r_mm.is_finite() && r_mm > 0.0) {
            return Err(not_positive(r_mm, r.span));
        }
        let (off, along, _) = polyline_nearest(guide, point);
        let reach = ROUND_REACH + 2.0 * r_mm;
        if off > reach {
            return Err(feature_error(
                kind,
                format!(
                    "this radius is placed {} mm from the edge being rounded; it must lie within {} mm",
                    round(off),
                    round(reach)
                ),
                at.span,
                "this point",
                "put each radius's `at` on (or near) the edge or round it belongs to",
            ));
        }
        given.push((along, r_mm));
        spans.push(item.span);
    }
    RadiusLaw::through(&given, total, closed).map_err(|e| {
        let span = match &e {
            RadiusError::NotPositive { index, .. } => spans[*index],
            RadiusError::SamePlace { second, .. } => spans[*second],
            RadiusError::Empty | RadiusError::Dips { .. } => value.span,
        };
        let help = match &e {
            RadiusError::Empty => "give one radius at least",
            RadiusError::SamePlace { .. } => "place each radius at its own point along the edge",
            _ => "give radii that change more gently, or more of them where the radius turns",
        };
        feature_error(kind, e.to_string(), span, "these radii", help)
    })
}

/// A kernel failure of a round, at the field it is about.
fn round_error(kind: &'static dyn FeatureKind, c: &Common, e: RoundError) -> Diagnostic {
    if let RoundError::Base(BaseError::NotSplit { face }) = &e {
        // Where the two sides join, as the designer finds it: the face's middle.
        let at = c
            .mesh
            .face_centroid(crate::geom::mesh::FaceId(*face))
            .map(show)
            .unwrap_or_else(|| format!("face {face}"));
        return feature_error(
            kind,
            format!(
                "the edge does not split the mesh near it in two: its two sides join round \
                 the face at {at}, where it ends inside the mesh, short of the mesh's edge"
            ),
            c.at_value.span,
            "the edge through this point",
            "round an edge that runs to the mesh's edge or round to its start",
        );
    }
    let (span, label, help) = match &e {
        RoundError::NoRoom { .. } => (
            c.radius_value.span,
            "this radius",
            "give a smaller radius: the ball must fit between the faces beside the edge",
        ),
        _ => (
            c.mesh_value.span,
            "this mesh",
            "check the mesh along the edge",
        ),
    };
    feature_error(kind, e.to_string(), span, label, help)
}

/// Builds the round of `block`.
fn build_round(block: &Block) -> Result<Value, Diagnostic> {
    let c = common(KIND, block)?;
    let (mesh, topology) = (&c.mesh, &c.topology);
    let theta = match block.get("angle") {
        Some(f) => as_angle(&f.value, block.units, "`angle`")?,
        None => DEFAULT_FEATURE_ANGLE,
    };
    let follow = match block.get("follow") {
        Some(f) => Some(as_point3(&f.value, block.units, "`follow`")?),
        None => None,
    };
    let sharp = sharp_edges(mesh, topology, theta);
    let node = nearest_sharp_node(mesh, topology, &sharp, c.at)
        .filter(|&(_, d)| d <= ROUND_REACH)
        .ok_or_else(|| {
            feature_error(
                KIND,
                format!(
                    "no sharp edge lies within {ROUND_REACH} mm of the point: no edge there turns by \
                     more than {} deg",
                    round(theta.to_degrees())
                ),
                c.at_value.span,
                "this point",
                "put `at` on the sharp edge to round (within 5 mm of one of its nodes), or lower \
                 the feature `angle`",
            )
        })?;
    let chain = chain_through(mesh, topology, &sharp, node.0, follow).map_err(|e| {
        let place = |v: u32| show(mesh.positions()[v as usize]);
        match e {
            ChainError::Branch { node, edges } => feature_error(
                KIND,
                format!(
                    "the chain of sharp edges branches at {}, where {edges} sharp edges meet",
                    place(node)
                ),
                c.at_value.span,
                "the chain through this point",
                "give `follow = (x, y, z)`, the way to go on at the branch",
            ),
            ChainError::NotManifold { node } => feature_error(
                KIND,
                format!(
                    "the mesh is not manifold and consistently oriented at {}, on the chain",
                    place(node)
                ),
                c.mesh_value.span,
                "this mesh",
                "give a mesh whose edges along the chain each join two faces wound alike",
            ),
            ChainError::NotSharp { .. } => feature_error(
                KIND,
                e.to_string(),
                c.at_value.span,
                "this point",
                "put `at` on a sharp edge",
            ),
        }
    })?;
    // An open chain must run to the mesh's edge at both ends: where it stops inside,
    // the faces on its two sides join round its end and no ball has one side to roll on.
    if !chain.closed {
        let ends = [chain.nodes.first(), chain.nodes.last()];
        if let Some(&end) = ends
            .into_iter()
            .flatten()
            .find(|&&v| !topology.is_boundary_vertex(v))
        {
            return Err(feature_error(
                KIND,
                format!(
                    "the chain of sharp edges ends inside the mesh at {}, where the edges go \
                     on turning by less than the feature angle",
                    show(mesh.positions()[end.index()])
                ),
                c.at_value.span,
                "the edge through this point",
                "round an edge that runs to the mesh's edge or round to its start, or lower \
                 the feature `angle` if the edge fades out",
            ));
        }
    }
    let guide = chain_polyline(mesh, &chain);
    let law = radius_law(KIND, c.radius_value, block.units, &guide, chain.closed)?;
    let rounded = round_chain(mesh, topology, &chain, &law, c.tolerance)
        .map_err(|e| round_error(KIND, &c, e))?;
    let length = polyline_length(&guide);
    Ok(output(
        KIND,
        block,
        rounded,
        radius_quality(&law, length, block.span),
    ))
}

/// Builds the re-round of `block`.
fn build_reround(block: &Block) -> Result<Value, Diagnostic> {
    let c = common(REROUND, block)?;
    let (mesh, topology) = (&c.mesh, &c.topology);
    let band = match block.get("band") {
        Some(f) => {
            let b = as_number(&f.value, "`band`")?;
            if !(b.is_finite() && b > 0.0 && b < 1.0) {
                return Err(feature_error(
                    REROUND,
                    format!("the band must lie between 0 and 1, not {}", round(b)),
                    f.value.span,
                    "not a band",
                    "give how far a node's curvature may differ from the picked node's, as a \
                     share of it, such as `band = 0.25`",
                ));
            }
            b
        }
        None => DEFAULT_BAND,
    };
    let node = mesh
        .positions()
        .iter()
        .enumerate()
        .map(|(i, p)| (i, p.distance(c.at)))
        .min_by(|a, b| a.1.total_cmp(&b.1).then(a.0.cmp(&b.0)))
        .filter(|&(_, d)| d <= ROUND_REACH)
        .ok_or_else(|| {
            feature_error(
                REROUND,
                format!("no node of the mesh lies within {ROUND_REACH} mm of the point"),
                c.at_value.span,
                "this point",
                "put `at` on the round to change",
            )
        })?;
    let curvatures = CurvatureAt::new(mesh, topology);
    let found = find_round(
        mesh,
        topology,
        &|v| curvatures.at(v),
        VertexId(node.0 as u32),
        band,
    )
    .map_err(|e| {
        let help = match &e {
            FindError::Flat | FindError::NoCurvature => "put `at` on the round to change",
            FindError::NotTwoSides { .. } | FindError::NotAStrip { .. } => {
                "narrow the `band`, or pick a round that runs from edge to edge of the mesh \
                     or round to its start"
            }
        };
        feature_error(
            REROUND,
            e.to_string(),
            c.at_value.span,
            "the round at this point",
            help,
        )
    })?;
    let law = radius_law(
        REROUND,
        c.radius_value,
        block.units,
        &found.guide,
        found.closed,
    )?;
    let length = found.length();
    let (smallest, _) = law.range(length);
    if smallest < found.radius * (1.0 - 1e-3) {
        return Err(feature_error(
            REROUND,
            format!(
                "the round found here has a radius of {} mm; a re-round can only widen it, and \
                 the new radius falls to {} mm",
                round(found.radius),
                round(smallest)
            ),
            c.radius_value.span,
            "this radius",
            "give radii of at least the round's own: a tighter round needs the sharp edge \
             back (round the mesh before it was rounded)",
        ));
    }
    let site = reround_site(mesh, topology, &found, law.mean(length))
        .map_err(|e| round_error(REROUND, &c, RoundError::Base(e)))?;
    let rounded = round_site(mesh, topology, &site, &law, c.tolerance)
        .map_err(|e| round_error(REROUND, &c, e))?;
    let mut quality = found_quality(&found, block.span);
    quality.extend(radius_quality(&law, length, block.span));
    Ok(output(REROUND, block, rounded, quality))
}

/// The round `reround` found, as `inspect` reports it: its mean radius, length and
/// node count.
fn found_quality(found: &ExistingRound, span: Span) -> Vec<(String, Value)> {
    vec![
        ("found_radius".to_string(), mm(found.radius, span)),
        ("found_length".to_string(), mm(found.length(), span)),
        ("found_nodes".to_string(), count(found.nodes.len(), span)),
    ]
}

/// The smallest and largest radius along the round.
fn radius_quality(law: &RadiusLaw, length: f64, span: Span) -> Vec<(String, Value)> {
    let (lo, hi) = law.range(length);
    vec![
        ("radius_min".to_string(), mm(lo, span)),
        ("radius_max".to_string(), mm(hi, span)),
    ]
}

/// A point as a designer reads it.
fn show(p: DVec3) -> String {
    format!("({}, {}, {})", round(p.x), round(p.y), round(p.z))
}

/// The value of a built round: its pieces and `quality` (the balls, the round's faces,
/// how far the balls were re-centred, the faces the trim lines split and the nodes
/// snapped onto them, and `extra`).
fn output(
    kind: &'static dyn FeatureKind,
    block: &Block,
    rounded: Rounded,
    extra: Vec<(String, Value)>,
) -> Value {
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
    let mut quality = vec![
        ("balls".to_string(), count(rounded.balls.len(), span)),
        ("round_faces".to_string(), count(rounded.round_faces, span)),
        ("recentred".to_string(), mm(moved, span)),
        ("split_faces".to_string(), count(rounded.split_faces, span)),
        (
            "snapped_nodes".to_string(),
            count(rounded.snapped_nodes, span),
        ),
    ];
    quality.extend(extra);
    feature_value(kind, span, fields, quality, rounded)
}
