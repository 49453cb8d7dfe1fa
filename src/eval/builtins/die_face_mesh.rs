//! The whole die face as one conforming shell mesh for forming simulation (issue 18):
//! the product, the step draw's patches and the binder's patches meshed with quads so
//! that every seam carries the same nodes on both sides
//! (`geom::mesh::quad::shell`).
//!
//! ```text
//! let die_mesh = die_face_mesh({ product: fender, step_draw: addendum, binder: binder },
//!                              size: 10 mm, sizes: { product: 5 mm }, tolerance: 0.3 mm)
//! ```
//!
//! The value is a record with one mesh per feature, under the names given: in a deck
//! each is one shell part, and they share the seam nodes (the product outline between
//! the product and the step draw, the punch opening between the step draw and the
//! binder).

use std::sync::Arc;

use crate::diag::Diagnostic;
use crate::die::model::DieFace;
use crate::geom::mesh::quad::shell::{quad_mesh_shell, ShellMeshError};
use crate::geom::mesh::quad::surface::{SurfaceMeshError, SurfaceMeshOptions};
use crate::geom::mesh::quad::QuadError;
use crate::geom::sew::{sew, Face, DIE_FACE_TOLERANCE};

use super::super::model::product_faces;
use super::super::value::{Data, Record, Value};
use super::args::{bad_argument, what};
use super::meshes::check_size;
use super::{as_length, opt, req, Builtin, Call};

/// The die-face meshing builtin.
pub static BUILTINS: &[Builtin] = &[Builtin {
    name: "die_face_mesh",
    params: &[
        req("features"),
        req("size"),
        opt("sizes"),
        opt("tolerance"),
        opt("max_elements"),
    ],
    doc: "the die face's features (a record such as `{ product: fender, step_draw: addendum, binder: binder }`) meshed with quads of about `size` (per feature from `sizes`, a record under the same names), finer where a chord would sag more than `tolerance` (default size / 20); neighbouring patches share their seam nodes exactly; the value is a record of one mesh per feature",
    run: die_face_mesh,
}];

/// One feature's faces: the name it was given and its faces of the die face.
struct Feature<'a> {
    name: String,
    value: &'a Value,
    faces: Vec<Face>,
}

/// `die_face_mesh(features, size, sizes?, tolerance?, max_elements?)`.
fn die_face_mesh(call: &Call) -> Result<Data, Diagnostic> {
    let features_value = call.required("features")?;
    let Data::Record(record) = &features_value.data else {
        return Err(call.bad(
            features_value,
            "features",
            "a record of the die face's features, such as `{ product: fender, step_draw: addendum, binder: binder }`",
        ));
    };
    let size = positive_length(
        call,
        "size",
        "give the element edge length forming simulation wants, such as `10 mm`",
    )?;
    let mut features = Vec::with_capacity(record.fields.len());
    for (name, value) in &record.fields {
        let mut faces = Vec::new();
        faces_of(name, value, &mut faces)?;
        features.push(Feature {
            name: name.clone(),
            value,
            faces,
        });
    }
    if features.iter().all(|f| f.faces.is_empty()) {
        return Err(bad_argument(
            call,
            "features",
            "none of these features has a face of the die face",
            "give the product, the step draw and the blankholder",
        ));
    }
    let mut feature_size = vec![size; features.len()];
    if let Some(v) = call.arg("sizes") {
        let Data::Record(sizes) = &v.data else {
            return Err(call.bad(
                v,
                "sizes",
                "a record of sizes under the features' names, such as `{ product: 5 mm }`",
            ));
        };
        for (name, s) in &sizes.fields {
            let Some(k) = features.iter().position(|f| &f.name == name) else {
                return Err(Diagnostic::new(
                    "die::bad_argument",
                    format!("`sizes` names `{name}`, which is not one of the features"),
                    s.span,
                    "no feature of this name",
                )
                .with_help(format!(
                    "the features are: {}",
                    features
                        .iter()
                        .map(|f| f.name.as_str())
                        .collect::<Vec<_>>()
                        .join(", ")
                )));
            };
            let h = as_length(s, call.units, &what(call, "sizes"))?;
            if !(h.is_finite() && h > 0.0) {
                return Err(Diagnostic::new(
                    "die::bad_argument",
                    format!("the element size of `{name}` must be above 0 mm, not {h} mm"),
                    s.span,
                    "this size",
                )
                .with_help("give the element edge length for this feature, such as `5 mm`"));
            }
            feature_size[k] = h;
        }
    }
    // A chordal tolerance of size / 20 unless given.
    let mut options = SurfaceMeshOptions::at_size(size);
    if call.arg("tolerance").is_some() {
        options.quad.chord_tolerance = positive_length(
            call,
            "tolerance",
            "give how far an element's chord may sag off the surface, such as `0.2 mm`",
        )?;
    }
    if call.arg("max_elements").is_some() {
        options.quad.max_elements = call.count("max_elements")?;
    }
    // Which feature each face belongs to, in the order they are sewn.
    let mut owner = Vec::new();
    let mut faces = Vec::new();
    for (k, f) in features.iter().enumerate() {
        owner.extend(std::iter::repeat_n(k, f.faces.len()));
        faces.extend(f.faces.iter().cloned());
    }
    let sizes: Vec<f64> = owner.iter().map(|&k| feature_size[k]).collect();
    let shell =
        sew(faces, DIE_FACE_TOLERANCE).map_err(|e| call.kernel_error(e, Some("features")))?;
    let meshed = quad_mesh_shell(&shell, &sizes, &options)
        .map_err(|e| shell_error(call, &e, &features, &owner))?;
    check_size(call, "size", "the die-face mesh", meshed.positions.len())?;
    let mut fields = Vec::with_capacity(features.len());
    for (k, f) in features.iter().enumerate() {
        let mine: Vec<usize> = (0..owner.len()).filter(|&i| owner[i] == k).collect();
        if mine.is_empty() {
            continue;
        }
        let mesh = meshed.mesh_of(&mine).map_err(|e| {
            bad_argument(
                call,
                "features",
                format!("the mesh of `{}` could not be made: {e}", f.name),
                "check the feature's surfaces",
            )
        })?;
        fields.push((
            f.name.clone(),
            Value::new(Data::Mesh(Arc::new(mesh)), f.value.span),
        ));
    }
    Ok(Data::Record(Arc::new(Record {
        kind: None,
        fields,
        feature: None,
    })))
}

/// A length argument above 0 mm.
fn positive_length(call: &Call, arg: &str, help: &str) -> Result<f64, Diagnostic> {
    let h = call.length(arg)?;
    if h.is_finite() && h > 0.0 {
        Ok(h)
    } else {
        Err(bad_argument(
            call,
            arg,
            format!("`{arg}` must be above 0 mm, not {h} mm"),
            help,
        ))
    }
}

/// The die-face faces of one feature: a product (a trimmed surface, a surface, or a
/// list of them), or a step draw's or blankholder's patches.
fn faces_of(name: &str, value: &Value, out: &mut Vec<Face>) -> Result<(), Diagnostic> {
    if let Data::Record(r) = &value.data {
        if let Some(f) = &r.feature {
            let mut face = DieFace::default();
            f.kind.die_face(name, r, &mut face);
            if face.faces.is_empty() {
                let kind = r.kind.as_deref().unwrap_or("feature");
                let help = if kind == "bead" {
                    "a draw bead goes to a deck as a line bead (`*CONTACT_DRAWBEAD`): declare the bead and it is written beside the mesh"
                } else {
                    "give the product, the step draw and the blankholder"
                };
                return Err(Diagnostic::new(
                    "die::bad_argument",
                    format!("`{name}` is a {kind}, which has no face of the die face to mesh"),
                    value.span,
                    "not a face of the die face",
                )
                .with_help(help));
            }
            out.extend(face.faces);
            return Ok(());
        }
    }
    let before = out.len();
    product_faces(name, value, out);
    if out.len() == before {
        return Err(Diagnostic::new(
            "die::type",
            format!(
                "`{name}` in `features` of `die_face_mesh` must be a product surface, a step draw or a blankholder, not {}",
                value.data.type_name()
            ),
            value.span,
            "not a face of the die face",
        )
        .with_help("give the product, the step draw and the blankholder"));
    }
    Ok(())
}

/// The element count refused, at `size`.
fn too_many(call: &Call, estimate: usize, limit: usize) -> Diagnostic {
    let place = call
        .decl
        .map_or_else(String::new, |d| format!(" (in `{d}`)"));
    bad_argument(
        call,
        "size",
        format!("`die_face_mesh` would make about {estimate} elements at this size, more than the limit of {limit}{place}"),
        "give a larger `size` (or larger `sizes`), or raise `max_elements`",
    )
}

/// A shell meshing failure told at the feature whose face failed.
fn shell_error(
    call: &Call,
    err: &ShellMeshError,
    features: &[Feature],
    owner: &[usize],
) -> Diagnostic {
    match err {
        ShellMeshError::TooMany { estimate, limit } => too_many(call, *estimate, *limit),
        ShellMeshError::Size { face, size } => {
            let f = &features[owner[*face]];
            bad_argument(
                call,
                "sizes",
                format!(
                    "the element size of `{}` must be above 0 mm, not {size} mm",
                    f.name
                ),
                "give a positive size",
            )
        }
        ShellMeshError::Face { face, name, error } => {
            let f = &features[owner[*face]];
            let (why, help) = match error {
                SurfaceMeshError::Region(QuadError::TooMany { estimate, limit }) => {
                    return too_many(call, *estimate, *limit)
                }
                SurfaceMeshError::Distorted { .. } | SurfaceMeshError::NoConvergence { .. } => (
                    error.to_string(),
                    "the patch folds over itself seen from the plane it is meshed in; check its sections, or split it",
                ),
                SurfaceMeshError::OffSurface { .. } => (
                    error.to_string(),
                    "the patch's edges do not lie on its neighbours' within the sewing tolerance (0.01 mm): check that the features meet",
                ),
                _ => (error.to_string(), "check the feature's patches and the sizes"),
            };
            let place = match call.decl {
                Some(d) => format!(" (in `{d}`)"),
                None => String::new(),
            };
            Diagnostic::new(
                "die::quad_mesh",
                format!(
                    "`die_face_mesh` failed on the patch `{name}` of `{}`: {why}{place}",
                    f.name
                ),
                f.value.span,
                format!("the patch `{name}` of this feature"),
            )
            .with_help(help)
        }
    }
}
