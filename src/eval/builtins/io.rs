//! Reading files: the product mesh from OBJ.
//!
//! Paths are relative to the directory of the script that names them and must stay
//! inside the project root (after resolving `..` and symbolic links), so a script
//! cannot read arbitrary files of the machine it is built on. The OBJ is read by
//! `paths::read_regular` (a regular file within `file_bytes`) and parsed by
//! [`parse_obj`] (the file's own node numbering kept across groups; the material
//! library an `mtllib` line names is never opened); the mesh is held to
//! `mesh_vertices`.

use std::path::PathBuf;
use std::sync::Arc;

use crate::diag::Diagnostic;
use crate::geom::mesh::obj::{parse_obj, ObjError};
use crate::limits::Limit;
use crate::syntax::Span;

use super::super::paths::{read_regular, record_read, refusal_diagnostic, resolve_in_root};
use super::super::value::Data;
use super::args::span_of;
use super::{req, Builtin, Call};

/// The file builtins.
pub static BUILTINS: &[Builtin] = &[Builtin {
    name: "read_obj",
    params: &[req("path")],
    doc: "the mesh in an OBJ file, one node per `v` line shared by every face naming it (triangles and quads kept; objects and groups become named face groups)",
    run: read_obj,
}];

/// The file `path` names, relative to the calling script, checked to lie in the root.
fn resolve(call: &Call, path: &str) -> Result<PathBuf, Diagnostic> {
    resolve_in_root(path, call.dir, call.root, span_of(call, "path")).map_err(|d| {
        if d.code == "die::path_escapes_root" {
            d.with_label(call.span, "read here")
        } else {
            d
        }
    })
}

/// `read_obj(path)`: the file read through the root and size checks, parsed by
/// [`parse_obj`], held to `mesh_vertices`.
fn read_obj(call: &Call) -> Result<Data, Diagnostic> {
    let path = call.string("path")?;
    let full = resolve(call, &path)?;
    let span = span_of(call, "path");
    let bytes = read_regular(&full, call.budget.limits().get(Limit::FileBytes))
        .map_err(|r| refusal_diagnostic(&path, &r, span, call.budget.limits()))?;
    record_read(&full);
    let limit = call.budget.limits().get(Limit::MeshVertices);
    let max_vertices = usize::try_from(limit).unwrap_or(usize::MAX);
    let mesh = parse_obj(&bytes, max_vertices).map_err(|e| match e {
        // The whole count, to say how far over the limit the file is.
        ObjError::TooManyVertices { .. } => {
            match check_vertex_count(call, &path, count_vertex_lines(&bytes)) {
                Err(d) => d,
                // The lines counted and the reader's count agree; were they ever not to,
                // the reader's refusal still stands.
                Ok(()) => bad_obj(&path, span, &e.to_string()),
            }
        }
        other => bad_obj(&path, span, &other.to_string()),
    })?;
    Ok(Data::Mesh(Arc::new(mesh)))
}

/// The diagnostic for an OBJ that is not a mesh, at the path argument.
fn bad_obj(path: &str, span: Span, reason: &str) -> Diagnostic {
    Diagnostic::new(
        "die::bad_obj",
        format!("cannot read `{path}` as OBJ: {reason}"),
        span,
        "this file",
    )
    .with_help("the file must be a Wavefront OBJ mesh: `v` lines, and `f` lines of three or more distinct vertices that the file has")
}

/// How many vertex position lines (`v x y z`) an OBJ text holds.
fn count_vertex_lines(bytes: &[u8]) -> usize {
    bytes
        .split(|&b| b == b'\n' || b == b'\r')
        .filter(|line| {
            let line = line.trim_ascii_start();
            line.starts_with(b"v") && line.get(1).is_some_and(|b| b.is_ascii_whitespace())
        })
        .count()
}

/// Refuses an OBJ of more than `mesh_vertices` vertices, at the path argument.
fn check_vertex_count(call: &Call, path: &str, vertices: usize) -> Result<(), Diagnostic> {
    super::meshes::check_size(call, "path", &format!("`{path}`"), vertices)
}
