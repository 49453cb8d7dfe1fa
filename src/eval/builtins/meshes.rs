//! Making meshes in the script: a sharp-edged tool mesh through rows of points (a die
//! modelled with sharp shoulders, to round them), and a surface tessellated to a mesh
//! (so a die face built in the script can be rounded or checked like a mesh read from
//! OBJ). Both are held to the `mesh_vertices` limit.

use std::sync::Arc;

use glam::DVec3;

use crate::diag::Diagnostic;
use crate::geom::mesh::{Face, Mesh};
use crate::geom::tessellate::{tessellate_surface, tessellate_trimmed, Tolerance};
use crate::limits::Limit;

use super::super::value::Data;
use super::args::{bad_argument, span_of, what};
use super::{as_length, as_point3, opt, req, Builtin, Call};

/// The mesh builtins.
pub static BUILTINS: &[Builtin] = &[
    Builtin {
        name: "mesh_through",
        params: &[req("rows")],
        doc: "the triangle mesh through rows of 3-D points (each row as long as the first), each cell between neighbouring rows split in two: a sharp-edged tool mesh from its sections",
        run: mesh_through,
    },
    Builtin {
        name: "tessellate",
        params: &[req("surface"), opt("tolerance")],
        doc: "the triangle mesh of a surface or trimmed surface (or a list of them, joined where their nodes meet), within a chordal tolerance (default 0.05 mm)",
        run: tessellate,
    },
    Builtin {
        name: "free_edges",
        params: &[req("mesh"), opt("outer")],
        doc: "a mesh's free edges: `count`, `loops` (each `{ nodes, length, span, at, outer }`), `holes` and `outer_length`; the outer boundary is the loop enclosing the others, or the loop nearest the point `outer`",
        run: free_edges,
    },
];

/// How near (mm) the nodes of neighbouring surfaces' meshes must lie to be joined when
/// a list of surfaces is tessellated.
const JOIN: f64 = 1e-6;

/// The chordal tolerance `tessellate` keeps when none is given (mm).
const DEFAULT_TOLERANCE: f64 = 0.05;

/// Refuses a mesh of more than `mesh_vertices` vertices, at argument `arg`; `subject`
/// names it in the message (the mesh, or the file it is read from).
pub(super) fn check_size(
    call: &Call,
    arg: &str,
    subject: &str,
    vertices: usize,
) -> Result<(), Diagnostic> {
    let limit = call.budget.limits().get(Limit::MeshVertices);
    if vertices as u64 <= limit {
        return Ok(());
    }
    Err(Diagnostic::new(
        "die::limit::mesh_vertices",
        format!(
            "{subject} has {vertices} vertices, more than the `{}` limit allows",
            Limit::MeshVertices
        ),
        span_of(call, arg),
        "this mesh is too large",
    )
    .with_help(Limit::MeshVertices.help(call.budget.limits())))
}

/// `mesh_through(rows)`: node `(i, j)` is point `i` of row `j`; the cell from
/// `(i, j)` to `(i + 1, j + 1)` is split along that diagonal, both triangles wound
/// counter-clockwise in `(i, j)`, so the mesh's normals face `along row x across
/// rows`. The edges between cells are where the rows turn: sharp where the sections
/// are.
fn mesh_through(call: &Call) -> Result<Data, Diagnostic> {
    let rows_value = call.list("rows")?;
    let what = what(call, "rows");
    if rows_value.len() < 2 {
        return Err(bad_argument(
            call,
            "rows",
            format!(
                "`mesh_through` needs two rows at least, not {}",
                rows_value.len()
            ),
            "give the sections in order, each a list of 3-D points",
        ));
    }
    let mut positions: Vec<DVec3> = Vec::new();
    let mut width = 0;
    for (j, row) in rows_value.iter().enumerate() {
        let Data::List(points) = &row.data else {
            return Err(call.bad(row, "rows", "a list of rows, each a list of 3-D points"));
        };
        if j == 0 {
            width = points.len();
            if width < 2 {
                return Err(bad_argument(
                    call,
                    "rows",
                    format!("a row needs two points at least, not {width}"),
                    "give each section as a list of 3-D points",
                ));
            }
        } else if points.len() != width {
            return Err(Diagnostic::new(
                "die::bad_argument",
                format!(
                    "row {j} has {} points but the first has {width}: every row needs as many",
                    points.len()
                ),
                row.span,
                "this row",
            )
            .with_help("give every section the same number of points, corner for corner"));
        }
        check_size(call, "rows", "the mesh", (j + 1) * width)?;
        for p in points.iter() {
            positions.push(as_point3(p, call.units, &what)?);
        }
    }
    let id = |i: usize, j: usize| (j * width + i) as u32;
    let mut faces = Vec::with_capacity(2 * (width - 1) * (rows_value.len() - 1));
    for j in 0..rows_value.len() - 1 {
        for i in 0..width - 1 {
            faces.push(Face::triangle(id(i, j), id(i + 1, j), id(i + 1, j + 1)));
            faces.push(Face::triangle(id(i, j), id(i + 1, j + 1), id(i, j + 1)));
        }
    }
    let mesh = Mesh::new(positions, faces).map_err(|e| call.kernel_error(e, Some("rows")))?;
    Ok(Data::Mesh(Arc::new(mesh)))
}

/// `tessellate(surface, tolerance?)`.
fn tessellate(call: &Call) -> Result<Data, Diagnostic> {
    let tolerance = match call.arg("tolerance") {
        Some(v) => {
            let t = as_length(v, call.units, &what(call, "tolerance"))?;
            if !(t.is_finite() && t > 0.0) {
                return Err(bad_argument(
                    call,
                    "tolerance",
                    format!("the tolerance must be above 0 mm, not {t} mm"),
                    "give how far the mesh may stray from the surface, such as `0.05 mm`",
                ));
            }
            t
        }
        None => DEFAULT_TOLERANCE,
    };
    let tol = Tolerance::new(tolerance).map_err(|e| call.kernel_error(e, Some("tolerance")))?;
    let surface = call.required("surface")?;
    let one = |value: &super::super::value::Value| -> Result<Mesh, Diagnostic> {
        let meshed = match &value.data {
            Data::Surface(s) => tessellate_surface(s, &tol),
            Data::Trimmed(t) => tessellate_trimmed(t, &tol),
            _ => {
                return Err(call.bad(
                    value,
                    "surface",
                    "a surface or a trimmed surface, or a list of them",
                ))
            }
        }
        .map_err(|e| call.kernel_error(e, Some("surface")))?;
        check_size(call, "surface", "the mesh", meshed.positions.len())?;
        meshed
            .to_mesh()
            .map_err(|e| call.kernel_error(e, Some("surface")))
    };
    let mesh = match &surface.data {
        Data::List(items) => {
            // Each surface's mesh, joined where their nodes meet: where neighbouring
            // surfaces' tessellations do not share nodes, free edges stay between them,
            // for `free_edges` to find.
            let mut all = Mesh::new(Vec::new(), Vec::new())
                .map_err(|e| call.kernel_error(e, Some("surface")))?;
            for item in items.iter() {
                all.append(&one(item)?)
                    .map_err(|e| call.kernel_error(e, Some("surface")))?;
                check_size(call, "surface", "the mesh", all.vertex_count())?;
            }
            all.weld(JOIN)
                .map_err(|e| call.kernel_error(e, Some("surface")))?
        }
        _ => one(surface)?,
    };
    Ok(Data::Mesh(Arc::new(mesh)))
}

/// `free_edges(mesh, outer?)`.
fn free_edges(call: &Call) -> Result<Data, Diagnostic> {
    use super::super::value::{Quantity, Record, Value};
    use crate::geom::mesh::holes::loops;
    let value = call.required("mesh")?;
    let Data::Mesh(mesh) = &value.data else {
        return Err(call.bad(value, "mesh", "a mesh"));
    };
    let outer = match call.arg("outer") {
        Some(v) => Some(as_point3(v, call.units, &what(call, "outer"))?),
        None => None,
    };
    let mesh = mesh.triangulated();
    let found = loops::free_edges(&mesh, outer);
    let span = call.span;
    let number = |v: f64| Value::new(Data::Number(Quantity::bare(v)), span);
    let length = |v: f64| Value::new(Data::Number(Quantity::length(v)), span);
    let record = |fields: Vec<(&str, Value)>| {
        Value::new(
            Data::Record(Arc::new(Record {
                kind: None,
                fields: fields
                    .into_iter()
                    .map(|(n, v)| (n.to_string(), v))
                    .collect(),
                feature: None,
            })),
            span,
        )
    };
    let loop_values: Vec<Value> = found
        .loops
        .iter()
        .map(|l| {
            record(vec![
                ("nodes", number(l.nodes.len() as f64)),
                ("length", length(l.length)),
                ("span", length(l.span)),
                ("at", Value::point3(l.centre, span)),
                ("outer", Value::new(Data::Bool(l.outer), span)),
            ])
        })
        .collect();
    let outer_length: f64 = found
        .loops
        .iter()
        .filter(|l| l.outer)
        .map(|l| l.length)
        .sum();
    let holes = found.loops.iter().filter(|l| !l.outer).count();
    let result = record(vec![
        ("count", number(found.count as f64)),
        ("loops", Value::new(Data::List(Arc::new(loop_values)), span)),
        ("holes", number(holes as f64)),
        ("outer_length", length(outer_length)),
        ("open_chains", number(found.open_chains.len() as f64)),
        ("pieces", number(found.pieces as f64)),
    ]);
    Ok(result.data)
}
