//! The whole die face as one conforming shell mesh for forming simulation (issue 18):
//! the product, the step draw's patches, the binder's patches and the draw beads'
//! skins meshed with quads so that every seam carries the same nodes on both sides
//! (`geom::mesh::quad::shell`).
//!
//! ```text
//! let die_mesh = die_face_mesh({ product: fender, step_draw: addendum, binder: binder,
//!                                wheel_arch: wheel_arch },
//!                              size: 10 mm, sizes: { product: 5 mm }, tolerance: 0.3 mm)
//! ```
//!
//! The value is a record with one mesh per feature, under the names given: in a deck
//! each is one shell part, and they share the seam nodes (the product outline between
//! the product and the step draw, the punch opening between the step draw and the
//! binder, a bead's feet between the bead and the binder). A bead given here is set
//! into the binder it stands on (`geom::imprint`): the binder's elements stop at the
//! bead's feet and the bead's skin is meshed between them, for a simulation that
//! models the bead's geometry instead of a line bead.

use std::sync::Arc;

use rayon::prelude::*;

use crate::diag::Diagnostic;
use crate::die::model::DieFace;
use crate::geom::imprint::imprint;
use crate::geom::mesh::quad::shell::{quad_mesh_shell, ShellMeshError};
use crate::geom::mesh::quad::surface::{SurfaceMeshError, SurfaceMeshOptions};
use crate::geom::mesh::quad::QuadError;
use crate::geom::mesh::Mesh;
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
    doc: "the die face's features (a record such as `{ product: fender, step_draw: addendum, binder: binder }`, beads too, set into the binder) meshed with quads of about `size` (per feature from `sizes`, a record under the same names), finer where a chord would sag more than `tolerance` (default size / 20); neighbouring patches share their seam nodes exactly; the value is a record of one mesh per feature",
    run: die_face_mesh,
}];

/// One feature's faces: the name it was given, its faces of the die face, and its
/// bead skins to set into them.
struct Feature<'a> {
    name: String,
    value: &'a Value,
    faces: Vec<Face>,
    beads: Vec<Face>,
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
        let mut face = DieFace::default();
        faces_of(name, value, &mut face)?;
        features.push(Feature {
            name: name.clone(),
            value,
            faces: face.faces,
            beads: face.beads,
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
    let mut shell =
        sew(faces, DIE_FACE_TOLERANCE).map_err(|e| call.kernel_error(e, Some("features")))?;
    // The beads set into the faces they stand on; a face a bead cuts in two stays
    // its feature's.
    for (k, f) in features.iter().enumerate() {
        for bead in &f.beads {
            let done = imprint(&mut shell, bead.clone(), DIE_FACE_TOLERANCE).map_err(|e| {
                Diagnostic::new(
                    "die::quad_mesh",
                    format!(
                        "`die_face_mesh` could not set the bead `{}` into the die face: {e}",
                        f.name
                    ),
                    f.value.span,
                    "this bead",
                )
                .with_help("a bead meshed with the die face must stand on the binder given beside it, inside its outer edge and clear of its patch corners")
            })?;
            for &(_, from) in &done.split {
                owner.push(owner[from]);
            }
            owner.push(k);
        }
    }
    let sizes: Vec<f64> = owner.iter().map(|&k| feature_size[k]).collect();
    let meshed = quad_mesh_shell(&shell, &sizes, &options)
        .map_err(|e| shell_error(call, &e, &features, &owner))?;
    check_size(call, "size", "the die-face mesh", meshed.positions.len())?;
    // Each feature's mesh made side by side; the first failure in the features' order
    // is the one reported.
    let meshes: Vec<Option<Result<Mesh, String>>> = (0..features.len())
        .into_par_iter()
        .map(|k| {
            let mine: Vec<usize> = (0..owner.len()).filter(|&i| owner[i] == k).collect();
            (!mine.is_empty()).then(|| meshed.mesh_of(&mine))
        })
        .collect();
    let mut fields = Vec::with_capacity(features.len());
    for (f, mesh) in features.iter().zip(meshes) {
        let Some(mesh) = mesh else {
            continue;
        };
        let mesh = mesh.map_err(|e| {
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
/// list of them), a step draw's or blankholder's patches, or a bead's skin.
fn faces_of(name: &str, value: &Value, out: &mut DieFace) -> Result<(), Diagnostic> {
    if let Data::Record(r) = &value.data {
        if let Some(f) = &r.feature {
            let mut face = DieFace::default();
            f.kind.die_face(name, r, &mut face);
            if face.faces.is_empty() && face.beads.is_empty() {
                let kind = r.kind.as_deref().unwrap_or("feature");
                return Err(Diagnostic::new(
                    "die::bad_argument",
                    format!("`{name}` is a {kind}, which has no face of the die face to mesh"),
                    value.span,
                    "not a face of the die face",
                )
                .with_help("give the product, the step draw, the blankholder and the beads"));
            }
            out.faces.extend(face.faces);
            out.beads.extend(face.beads);
            return Ok(());
        }
    }
    let before = out.faces.len();
    product_faces(name, value, &mut out.faces);
    if out.faces.len() == before {
        return Err(Diagnostic::new(
            "die::type",
            format!(
                "`{name}` in `features` of `die_face_mesh` must be a product surface, a step draw, a blankholder or a bead, not {}",
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
