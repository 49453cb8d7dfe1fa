//! Moving geometry: translate, rotate, scale, tip a product into draw position, and
//! transform values (`rotation`, `translation`, `scaling`) applied with `transform_by`.
//!
//! Transforms act on every kind of geometry, and element-wise on lists of it: 3-D
//! curves, surfaces and meshes stay what they are; 2-D curves (at z = 0) and sketches
//! (placed through their view) become 3-D curves; points become 3-D points (2-D points
//! at z = 0). NURBS are transformed exactly (control points mapped, weights kept);
//! meshes move their vertices and rotate their normals.

use std::sync::Arc;

use glam::DMat3;

use crate::diag::Diagnostic;
use crate::geom::mesh::{Mesh, VertexId};
use crate::geom::{GeomError, Transform};

use super::super::value::{Data, Value};
use super::args::{bad_argument, direction3, opt_point3, point3, vector3, what};
use super::{as_point2, as_point3, opt, req, type_error, Builtin, Call};

/// The transform builtins.
pub static BUILTINS: &[Builtin] = &[
    Builtin { name: "translate", params: &[req("geom"), req("by")], doc: "geometry moved by a vector", run: translate },
    Builtin {
        name: "rotate",
        params: &[req("geom"), req("axis"), req("by"), opt("center")],
        doc: "geometry turned by an angle (right-handed) about an axis (\"x\", \"y\", \"z\" or a vector) through center (default the origin)",
        run: rotate,
    },
    Builtin { name: "scale", params: &[req("geom"), req("factor"), opt("center")], doc: "geometry scaled by a factor about center (default the origin)", run: scale },
    Builtin {
        name: "tip",
        params: &[req("geom"), req("about"), req("by"), opt("center")],
        doc: "a product tipped into draw position: turned by an angle about a horizontal axis (\"x\", \"y\" or a vector) through center",
        run: tip,
    },
    Builtin { name: "transform_by", params: &[req("geom"), req("t")], doc: "geometry moved by a transform value", run: transform_by },
    Builtin {
        name: "rotation",
        params: &[req("axis"), req("by"), opt("center")],
        doc: "the transform turning by an angle about an axis through center",
        run: rotation,
    },
    Builtin { name: "translation", params: &[req("by")], doc: "the transform moving by a vector", run: translation },
    Builtin { name: "scaling", params: &[req("factor"), opt("center")], doc: "the transform scaling by a factor about center", run: scaling },
];

/// `t` applied to a geometry value (recursively through lists).
fn apply(call: &Call, t: &Transform, v: &Value) -> Result<Data, Diagnostic> {
    let w = what(call, "geom");
    Ok(match &v.data {
        Data::Curve3(c) => Data::Curve3(Arc::new(t.apply_curve(c))),
        Data::Curve2(c) => Data::Curve3(Arc::new(t.apply_curve(&c.to_3d()))),
        Data::Sketch(s) => Data::Curve3(Arc::new(t.apply_curve(&s.to_3d()))),
        Data::Surface(s) => Data::Surface(Arc::new(t.apply_surface(s))),
        Data::Mesh(m) => Data::Mesh(Arc::new(transform_mesh(call, t, m)?)),
        Data::Tuple(items) if items.len() == 2 => point3(
            t.apply_point(as_point2(v, call.units, &w)?.extend(0.0)),
            v.span,
        ),
        Data::Tuple(_) => point3(t.apply_point(as_point3(v, call.units, &w)?), v.span),
        Data::List(items) => {
            let out = items
                .iter()
                .map(|x| apply(call, t, x).map(|d| Value::new(d, x.span)))
                .collect::<Result<Vec<_>, _>>()?;
            Data::List(Arc::new(out))
        }
        _ => {
            return Err(type_error(
                v,
                &w,
                "geometry: a curve, a sketch, a surface, a mesh, a point, or a list of them",
            ))
        }
    })
}

/// The mesh with its vertices moved and its normals turned (by the inverse transpose of
/// the linear part, renormalized). Mirroring transforms are refused: they would turn
/// the faces inside out.
fn transform_mesh(call: &Call, t: &Transform, m: &Mesh) -> Result<Mesh, Diagnostic> {
    let linear = DMat3::from_mat4(t.matrix());
    if linear.determinant() < 0.0 {
        return Err(bad_argument(
            call,
            "geom",
            "this transform mirrors, which would turn the mesh's faces inside out",
            "use a positive scale factor for meshes",
        ));
    }
    let mut out = m.clone();
    let fail = |e: GeomError| call.kernel_error(e, Some("geom"));
    for (i, p) in m.positions().iter().enumerate() {
        out.set_position(VertexId(i as u32), t.apply_point(*p))
            .map_err(fail)?;
    }
    if let Some(normals) = m.normals() {
        let normal_matrix = linear.inverse().transpose();
        let turned = normals
            .iter()
            .map(|n| (normal_matrix * *n).normalize_or_zero())
            .collect();
        out = out.with_normals(turned).map_err(fail)?;
    }
    Ok(out)
}

fn run_with(call: &Call, t: Result<Transform, GeomError>, arg: &str) -> Result<Data, Diagnostic> {
    let t = t.map_err(|e| {
        let arg = blamed(&e, arg);
        call.kernel_error(e, Some(arg))
    })?;
    apply(call, &t, call.required("geom")?)
}

/// The argument a transform's kernel error comes from: a non-finite angle is `by`'s, a
/// non-finite centre `center`'s, anything else `arg`'s (the axis, the offset, the factor).
fn blamed<'a>(e: &GeomError, arg: &'a str) -> &'a str {
    match e {
        GeomError::NotFinite {
            what: "rotation angle",
        } => "by",
        GeomError::NotFinite {
            what: "rotation centre" | "scale centre",
        } => "center",
        _ => arg,
    }
}

fn translate(call: &Call) -> Result<Data, Diagnostic> {
    run_with(call, Transform::translate(vector3(call, "by")?), "by")
}

fn rotate(call: &Call) -> Result<Data, Diagnostic> {
    let t = Transform::rotate_about_axis(
        opt_point3(call, "center")?,
        direction3(call, "axis")?,
        call.angle("by")?,
    );
    run_with(call, t, "axis")
}

fn factor(call: &Call) -> Result<f64, Diagnostic> {
    let f = call.number("factor")?;
    if f == 0.0 || !f.is_finite() {
        return Err(bad_argument(
            call,
            "factor",
            format!("a scale factor must be non-zero, not {f}"),
            "use a factor such as 1.02 (2 % larger)",
        ));
    }
    Ok(f)
}

fn scale(call: &Call) -> Result<Data, Diagnostic> {
    let t = Transform::scale_about(opt_point3(call, "center")?, factor(call)?);
    run_with(call, t, "factor")
}

fn tip(call: &Call) -> Result<Data, Diagnostic> {
    let axis = direction3(call, "about")?;
    if axis.normalize().z.abs() > 1.0 - 1e-12 {
        return Err(bad_argument(
            call,
            "about",
            "tipping turns a product about a horizontal axis, not about z",
            "tip about \"x\" or \"y\" (or a horizontal vector); use `rotate` to turn the product in the top view",
        ));
    }
    let t = Transform::rotate_about_axis(opt_point3(call, "center")?, axis, call.angle("by")?);
    run_with(call, t, "about")
}

fn transform_by(call: &Call) -> Result<Data, Diagnostic> {
    let v = call.required("t")?;
    let Data::Transform(t) = &v.data else {
        return Err(type_error(
            v,
            &what(call, "t"),
            "a transform such as `rotation(\"x\", 5 deg)`",
        ));
    };
    apply(call, t, call.required("geom")?)
}

fn rotation(call: &Call) -> Result<Data, Diagnostic> {
    let t = Transform::rotate_about_axis(
        opt_point3(call, "center")?,
        direction3(call, "axis")?,
        call.angle("by")?,
    );
    Ok(Data::Transform(Arc::new(t.map_err(|e| {
        let arg = blamed(&e, "axis");
        call.kernel_error(e, Some(arg))
    })?)))
}

fn translation(call: &Call) -> Result<Data, Diagnostic> {
    let t = Transform::translate(vector3(call, "by")?);
    Ok(Data::Transform(Arc::new(
        t.map_err(|e| call.kernel_error(e, Some("by")))?,
    )))
}

fn scaling(call: &Call) -> Result<Data, Diagnostic> {
    let t = Transform::scale_about(opt_point3(call, "center")?, factor(call)?);
    Ok(Data::Transform(Arc::new(
        t.map_err(|e| call.kernel_error(e, Some("factor")))?,
    )))
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec3;

    #[test]
    fn a_transforms_kernel_error_blames_the_argument_that_made_it() {
        let nan_angle = Transform::rotate_about_axis(DVec3::ZERO, DVec3::X, f64::NAN);
        assert_eq!(blamed(&nan_angle.unwrap_err(), "about"), "by");
        let nan_centre = Transform::rotate_about_axis(DVec3::splat(f64::NAN), DVec3::X, 1.0);
        assert_eq!(blamed(&nan_centre.unwrap_err(), "about"), "center");
        let zero_axis = Transform::rotate_about_axis(DVec3::ZERO, DVec3::ZERO, 1.0);
        assert_eq!(blamed(&zero_axis.unwrap_err(), "about"), "about");
    }
}
