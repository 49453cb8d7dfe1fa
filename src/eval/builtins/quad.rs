//! Quad meshing in the script (issue 18): a surface, or a region of it, meshed with
//! shell elements for forming simulation (`geom::mesh::quad::surface`).
//!
//! ```text
//! let panel_mesh = quad_mesh(panel, size: 20 mm, tolerance: 0.5 mm,
//!                            outline: door_outline, holes: [window, speaker])
//! ```
//!
//! Trim loops drawn in the top view (a sketch, a 2-D curve, 2-D points) are laid onto
//! the surface along press Z, as the designer draws them; loops given in 3-D (a 3-D
//! curve, 3-D points) must lie on the surface already (within 0.1 mm).

use std::sync::Arc;

use glam::DVec3;

use crate::diag::Diagnostic;
use crate::geom::mesh::quad::surface::{
    lay_onto, quad_mesh_surface, MeshPlane, SurfaceMeshError, SurfaceMeshOptions, SurfaceRegion,
};
use crate::geom::mesh::quad::QuadError;
use crate::geom::tessellate::{tessellate_curve, Tolerance};
use crate::geom::NurbsSurface;

use super::super::value::{Data, Value};
use super::args::{bad_argument, what};
use super::meshes::check_size;
use super::{as_length, as_point3, opt, req, Builtin, Call};

/// The quad meshing builtin.
pub static BUILTINS: &[Builtin] = &[Builtin {
    name: "quad_mesh",
    params: &[
        req("surface"),
        req("size"),
        opt("tolerance"),
        opt("outline"),
        opt("holes"),
        opt("plane"),
        opt("max_elements"),
    ],
    doc: "a surface (or the region inside `outline` and outside `holes`) meshed with quads of about `size`, finer where a chord would sag more than `tolerance` (default size / 20) off the surface; loops drawn in the top view are laid onto the surface along press Z, 3-D loops must lie on it; `plane` is \"projection\" (the paper's), \"parameters\", a view direction, or left out to choose",
    run: quad_mesh,
}];

/// How finely a trim curve is followed before it is meshed (mm).
const TRIM_TOLERANCE: f64 = 0.01;

/// `quad_mesh(surface, size, tolerance?, outline?, holes?, plane?, max_elements?)`.
fn quad_mesh(call: &Call) -> Result<Data, Diagnostic> {
    let surface_value = call.required("surface")?;
    let (surface, outline_of_trim): (Arc<NurbsSurface>, Option<Vec<DVec3>>) =
        match &surface_value.data {
            Data::Surface(s) => (s.clone(), None),
            Data::Trimmed(t) => {
                let s = t.surface();
                let outline = t
                    .outer()
                    .uv_samples()
                    .iter()
                    .map(|(_, uv)| s.point_at(uv.x, uv.y))
                    .collect::<Vec<_>>();
                (Arc::new(s.clone()), Some(outline))
            }
            _ => return Err(call.bad(surface_value, "surface", "a surface or a trimmed surface")),
        };
    let size = call.length("size")?;
    if !(size.is_finite() && size > 0.0) {
        return Err(bad_argument(
            call,
            "size",
            format!("the element size must be above 0 mm, not {size} mm"),
            "give the element edge length forming simulation wants, such as `5 mm`",
        ));
    }
    let mut options = SurfaceMeshOptions::at_size(size);
    if let Some(v) = call.arg("tolerance") {
        let t = as_length(v, call.units, &what(call, "tolerance"))?;
        if !(t.is_finite() && t > 0.0) {
            return Err(bad_argument(
                call,
                "tolerance",
                format!("the chordal tolerance must be above 0 mm, not {t} mm"),
                "give how far an element's chord may sag off the surface, such as `0.2 mm`",
            ));
        }
        options.quad.chord_tolerance = t;
    }
    if call.arg("max_elements").is_some() {
        options.quad.max_elements = call.count("max_elements")?;
    }
    options.plane = match call.arg("plane") {
        None => None,
        Some(v) => Some(plane_of(call, v)?),
    };
    let mut region = SurfaceRegion {
        outer: outline_of_trim,
        holes: Vec::new(),
    };
    if let Some(v) = call.arg("outline") {
        region.outer = Some(trim_loop(call, &surface, v, "outline")?);
    }
    if let Some(v) = call.arg("holes") {
        let Data::List(items) = &v.data else {
            return Err(call.bad(v, "holes", "a list of loops (curves, sketches or points)"));
        };
        for item in items.iter() {
            region.holes.push(trim_loop(call, &surface, item, "holes")?);
        }
    }
    let meshed = quad_mesh_surface(&surface, &region, &options)
        .map_err(|e| mesh_error(call, &e, region.outer.is_some()))?;
    check_size(call, "size", "the quad mesh", meshed.mesh.vertex_count())?;
    Ok(Data::Mesh(Arc::new(meshed.mesh)))
}

/// The `plane` argument: "projection", "parameters", "top", or a direction.
fn plane_of(call: &Call, v: &Value) -> Result<MeshPlane, Diagnostic> {
    match &v.data {
        Data::Str(s) if &**s == "projection" => Ok(MeshPlane::Projection),
        Data::Str(s) if &**s == "parameters" => Ok(MeshPlane::Parameters),
        Data::Str(s) if &**s == "top" => Ok(MeshPlane::View(DVec3::Z)),
        Data::Str(s) => Err(bad_argument(
            call,
            "plane",
            format!("`{s}` is not a plane to mesh in"),
            "give \"projection\", \"parameters\", \"top\", or a view direction such as `(0, 0, 1)`",
        )),
        _ => {
            let d = as_point3(v, call.units, &what(call, "plane"))?;
            if d.length() <= 0.0 {
                return Err(bad_argument(
                    call,
                    "plane",
                    "a view direction of no length".to_string(),
                    "give the direction the surface is seen along, such as `(0, 0, 1)`",
                ));
            }
            Ok(MeshPlane::View(d))
        }
    }
}

/// A trim loop as points on the surface: a top-view loop (sketch, 2-D curve, 2-D
/// points) laid onto it along press Z, a 3-D one taken as it is.
fn trim_loop(
    call: &Call,
    surface: &NurbsSurface,
    v: &Value,
    arg: &str,
) -> Result<Vec<DVec3>, Diagnostic> {
    let tol = Tolerance::new(TRIM_TOLERANCE).map_err(|e| call.kernel_error(e, Some(arg)))?;
    let (points, drawn_in_top_view): (Vec<DVec3>, bool) = match &v.data {
        Data::Curve3(c) => (
            tessellate_curve(c, &tol)
                .map_err(|e| call.kernel_error(e, Some(arg)))?
                .points,
            false,
        ),
        Data::Curve2(c) => (
            tessellate_curve(c, &tol)
                .map_err(|e| call.kernel_error(e, Some(arg)))?
                .points
                .into_iter()
                .map(|p| p.extend(0.0))
                .collect(),
            true,
        ),
        Data::Sketch(s) => (
            tessellate_curve(&s.to_3d(), &tol)
                .map_err(|e| call.kernel_error(e, Some(arg)))?
                .points,
            true,
        ),
        Data::List(items) => {
            let mut points = Vec::with_capacity(items.len());
            let mut flat = true;
            for p in items.iter() {
                match &p.data {
                    Data::Tuple(c) if c.len() == 2 => {
                        let q = super::as_point2(p, call.units, &what(call, arg))?;
                        points.push(q.extend(0.0));
                    }
                    _ => {
                        points.push(as_point3(p, call.units, &what(call, arg))?);
                        flat = false;
                    }
                }
            }
            (points, flat)
        }
        _ => {
            return Err(call.bad(
                v,
                arg,
                "a closed loop: a curve, a sketch, or a list of points",
            ))
        }
    };
    let mut points = points;
    // A closed curve's polyline ends where it starts.
    if points.len() > 1 && points[0].distance(points[points.len() - 1]) < 1e-9 {
        points.pop();
    }
    if !drawn_in_top_view {
        return Ok(points);
    }
    lay_onto(surface, DVec3::Z, &points).map_err(|k| {
        Diagnostic::new(
            "die::geometry",
            format!(
                "point {k} of this loop, at ({:.3}, {:.3}) in the top view, is not over the surface",
                points[k].x, points[k].y
            ),
            v.span,
            "this loop leaves the surface seen from above",
        )
        .with_help("draw the loop inside the surface's outline in the top view")
    })
}

/// A meshing failure told at the argument it blames.
fn mesh_error(call: &Call, err: &SurfaceMeshError, has_outline: bool) -> Diagnostic {
    // Loop 0 is the outline, the holes follow in their order.
    let loop_arg = |k: usize| {
        if k == 0 && has_outline {
            "outline"
        } else if k == 0 {
            "surface"
        } else {
            "holes"
        }
    };
    let loop_name = |k: usize| {
        if k == 0 {
            "the outline".to_string()
        } else {
            format!("hole {}", k - 1)
        }
    };
    let (arg, message, help): (&str, String, &str) = match err {
        SurfaceMeshError::OffSurface {
            loop_index,
            point,
            distance,
            at,
        } => (
            loop_arg(*loop_index),
            format!(
                "point {point} of {} lies {distance:.3} mm off the surface at ({:.3}, {:.3}, {:.3})",
                loop_name(*loop_index),
                at.x,
                at.y,
                at.z
            ),
            "a 3-D trim loop must lie on the surface; draw it in the top view to have it laid onto the surface",
        ),
        SurfaceMeshError::NoConvergence {
            loop_index, point, ..
        } => (
            loop_arg(*loop_index),
            format!(
                "point {point} of {} could not be placed on the surface: Newton did not converge",
                loop_name(*loop_index)
            ),
            "the surface may be too distorted there; check the loop lies on it",
        ),
        SurfaceMeshError::Distorted { at } => (
            "surface",
            format!(
                "the surface is too distorted for the plane it is meshed in near ({:.3}, {:.3}, {:.3})",
                at.x, at.y, at.z
            ),
            "mesh it in its parameters (`plane: \"parameters\"`) or split it into gentler patches",
        ),
        SurfaceMeshError::NoPlane => (
            "surface",
            err.to_string(),
            "give a view direction, such as `plane: \"top\"`",
        ),
        SurfaceMeshError::Region(QuadError::TooMany { estimate, limit }) => (
            "size",
            format!("this size would make about {estimate} elements, more than the limit of {limit}"),
            "give a larger `size` or `tolerance`, or raise `max_elements`",
        ),
        SurfaceMeshError::Region(QuadError::Crossing { first, second, .. }) => (
            loop_arg(*first.max(second)),
            if first == second {
                format!("{} crosses or touches itself", loop_name(*first))
            } else {
                format!(
                    "{} and {} cross or touch",
                    loop_name(*first),
                    loop_name(*second)
                )
            },
            "trim loops must neither cross nor touch: move or shrink one of them",
        ),
        SurfaceMeshError::Region(
            QuadError::Outside { loop_index: first }
            | QuadError::Degenerate { loop_index: first }
            | QuadError::NotFinite { loop_index: first },
        ) => (
            loop_arg(*first),
            format!("{} cannot be meshed: {err}", loop_name(*first)),
            "trim loops must be closed, enclose area, stay inside the outline and neither cross nor touch",
        ),
        SurfaceMeshError::Region(_) => (
            "surface",
            err.to_string(),
            "check the trim loops and the size",
        ),
    };
    let span = call.arg(arg).map_or(call.span, |v| v.span);
    let place = match call.decl {
        Some(d) => format!(" (in `{d}`, argument `{arg}`)"),
        None => format!(" (argument `{arg}`)"),
    };
    Diagnostic::new(
        "die::quad_mesh",
        format!("`quad_mesh` failed: {message}{place}"),
        span,
        format!("this `{arg}`"),
    )
    .with_help(help)
}
