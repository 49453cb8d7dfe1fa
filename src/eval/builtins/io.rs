//! Reading files: the product mesh from OBJ.
//!
//! Paths are relative to the directory of the script that names them and must stay
//! inside the project root (after resolving `..` and symbolic links), so a script
//! cannot read arbitrary files of the machine it is built on. The OBJ, and the MTL its
//! `mtllib` line names, are read by `paths::read_regular` (regular files within
//! `file_bytes`); the mesh is held to `mesh_vertices`.

use std::cell::RefCell;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use glam::DVec3;

use crate::diag::Diagnostic;
use crate::geom::mesh::{Face, FaceId, Mesh};
use crate::geom::GeomError;
use crate::limits::Limit;

use super::super::paths::{read_regular, record_read, refusal_diagnostic, resolve_in_root};
use super::super::value::Data;
use super::args::span_of;
use super::{req, Builtin, Call};

/// The file builtins.
pub static BUILTINS: &[Builtin] = &[Builtin {
    name: "read_obj",
    params: &[req("path")],
    doc: "the mesh in an OBJ file (triangles and quads kept; objects and groups become named face groups)",
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

fn read_obj(call: &Call) -> Result<Data, Diagnostic> {
    let path = call.string("path")?;
    let full = resolve(call, &path)?;
    let span = span_of(call, "path");
    let bytes = read_regular(&full, call.budget.limits().get(Limit::FileBytes))
        .map_err(|r| refusal_diagnostic(&path, &r, span, call.budget.limits()))?;
    record_read(&full);
    check_vertex_count(call, &path, count_vertex_lines(&bytes))?;
    let options = tobj::LoadOptions {
        triangulate: false,
        single_index: true,
        ..Default::default()
    };
    // tobj would open the MTL an `mtllib` line names by itself, anywhere; it is read
    // here instead, with the same root and file checks as the OBJ (its materials are
    // not used, so a missing MTL is no error, but one outside the root, or not a
    // regular file, or too large, is).
    let refused: RefCell<Option<Diagnostic>> = RefCell::new(None);
    let loaded = tobj::load_obj_buf(&mut bytes.as_slice(), &options, |mtl| {
        load_mtl(call, &full, mtl, &refused)
    });
    if let Some(d) = refused.into_inner() {
        return Err(d);
    }
    let (models, _materials) = loaded.map_err(|e| {
        Diagnostic::new(
            "die::bad_obj",
            format!("cannot read `{path}` as OBJ: {e}"),
            span,
            "this file",
        )
        .with_help("the file must be a Wavefront OBJ mesh (v, vn and f lines)")
    })?;
    let vertices: usize = models.iter().map(|m| m.mesh.positions.len() / 3).sum();
    check_vertex_count(call, &path, vertices)?;
    let mesh = to_mesh(&models).map_err(|e| {
        Diagnostic::new("die::bad_obj", format!("`{path}` is not a valid mesh: {e}"), span, "this file")
            .with_help("faces must name existing, distinct vertices; faces with more than four corners are split into triangles")
    })?;
    Ok(Data::Mesh(Arc::new(mesh)))
}

/// The materials of the MTL file `mtl` that the OBJ at `obj` names, read through the
/// root and file checks. A refusal is kept in `refused` (and ends the OBJ's reading as
/// an error); a missing file yields no materials.
fn load_mtl(
    call: &Call,
    obj: &Path,
    mtl: &Path,
    refused: &RefCell<Option<Diagnostic>>,
) -> tobj::MTLLoadResult {
    let span = span_of(call, "path");
    let shown = mtl.to_string_lossy();
    let refuse = |mut d: Diagnostic| {
        d.message = format!("the OBJ's material library (`mtllib`): {}", d.message);
        if d.code == "die::path_escapes_root" {
            d.help = Some("an OBJ's `mtllib` is read relative to the OBJ and must stay inside the project folder; move the material library beside the OBJ, or delete the `mtllib` line (dieface does not use materials)".into());
        }
        let d = d.with_label(call.span, "the OBJ read here names it in an `mtllib` line");
        refused.borrow_mut().get_or_insert(d);
        Err(tobj::LoadError::OpenFileFailed)
    };
    let full = match resolve_in_root(&shown, obj.parent(), call.root, span) {
        Ok(full) => full,
        Err(d) if d.code == "die::file_not_found" => return Err(tobj::LoadError::OpenFileFailed),
        Err(d) => return refuse(d),
    };
    match read_regular(&full, call.budget.limits().get(Limit::FileBytes)) {
        Ok(bytes) => {
            record_read(&full);
            tobj::load_mtl_buf(&mut bytes.as_slice())
        }
        Err(r) => refuse(refusal_diagnostic(&shown, &r, span, call.budget.limits())),
    }
}

/// How many vertex position lines (`v x y z`) an OBJ text holds: counted before the
/// file is parsed, so an OBJ too large for the `mesh_vertices` limit is refused
/// before its mesh is built.
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

/// One mesh from all the OBJ models, each model's faces forming the group of its name
/// (models of the same name share a group). Polygons with more than four corners are
/// split into a fan of triangles. Normals are kept if every model has one per vertex.
fn to_mesh(models: &[tobj::Model]) -> Result<Mesh, GeomError> {
    let mut positions = Vec::new();
    let mut normals = Vec::new();
    let mut all_normals = true;
    let mut faces = Vec::new();
    let mut groups: BTreeMap<String, Vec<FaceId>> = BTreeMap::new();
    let mut order: Vec<String> = Vec::new();
    for model in models {
        let m = &model.mesh;
        let base = positions.len() as u32;
        let count = m.positions.len() / 3;
        positions.extend(
            m.positions
                .chunks_exact(3)
                .map(|c| DVec3::new(c[0], c[1], c[2])),
        );
        if m.normals.len() == m.positions.len() {
            normals.extend(
                m.normals
                    .chunks_exact(3)
                    .map(|c| DVec3::new(c[0], c[1], c[2])),
            );
        } else {
            all_normals = false;
        }
        let arities: Vec<usize> = if m.face_arities.is_empty() {
            vec![3; m.indices.len() / 3]
        } else {
            m.face_arities.iter().map(|&a| a as usize).collect()
        };
        let mut at = 0;
        let first_face = faces.len();
        for arity in arities {
            let Some(corners) = m.indices.get(at..at + arity) else {
                return Err(GeomError::InvalidMesh {
                    reason: "a face refers past the end of the index list".into(),
                });
            };
            at += arity;
            if let Some(&bad) = corners.iter().find(|&&i| i as usize >= count) {
                return Err(GeomError::InvalidMesh {
                    reason: format!("a face refers to vertex {bad}, but the object has {count}"),
                });
            }
            let idx: Vec<u32> = corners.iter().map(|&i| base + i).collect();
            match idx.len() {
                3 | 4 => faces.push(Face::from_slice(&idx)?),
                n if n > 4 => {
                    for k in 1..n - 1 {
                        faces.push(Face::triangle(idx[0], idx[k], idx[k + 1]));
                    }
                }
                n => {
                    return Err(GeomError::InvalidMesh {
                        reason: format!("a face has {n} corners"),
                    })
                }
            }
        }
        if !groups.contains_key(&model.name) {
            order.push(model.name.clone());
        }
        groups
            .entry(model.name.clone())
            .or_default()
            .extend((first_face..faces.len()).map(|f| FaceId(f as u32)));
    }
    let mut mesh = Mesh::new(positions, faces)?;
    if all_normals && !normals.is_empty() {
        mesh = mesh.with_normals(normals.into_iter().map(|n| n.normalize_or_zero()).collect())?;
    }
    for name in order {
        let faces = groups.remove(&name).unwrap_or_default();
        mesh.add_group(name, faces)?;
    }
    Ok(mesh)
}
