//! An evaluated script as a [`DieModel`]: the boundary between the language and the
//! exporters.
//!
//! What becomes a part (everything else, numbers, strings, points, functions, is not
//! exported):
//!
//! * a surface, a trimmed surface (the product cut at its outline), a mesh;
//! * a 3-D curve, a sketch (placed in its view) or a 2-D curve (at z = 0);
//! * a list: one child per geometric element, named `name/0`, `name/1`, ... by the
//!   element's index in the list (so names stay stable when a non-geometric element
//!   sits in between). Children rather than one part with several shapes, so every
//!   part can be picked, hidden and traced on its own in a viewer;
//! * a record (a nested block or a record literal): one child per geometric field,
//!   named `rec/side-front` (the words of a field name joined by `-`);
//! * a feature: one child per piece its kind exports (`opening/front`,
//!   `binder/front`), its quality figures, its line bead; its die-face faces go to
//!   [`DieModel::die_face`].
//!
//! A top-level `let` whose surface a `product` trims (`let panel = ...`,
//! `product fender = trim(panel, outline)`) is not exported: the product is that panel,
//! cut at its outline.
//!
//! Part names are full paths from the declaration, so they are unique in the model.
//! Pieces carry the declaration's kind and colour, and the line of the expression that
//! made them when it lies inside the declaration, else the declaration's line. A list
//! or record without any geometry gives no part.

use std::sync::Arc;

use glam::DVec3;

use crate::diag::Sources;
use crate::die::model::{DieModel, Figure, FigureValue, Part, Shape, PLAIN_COLOR};
use crate::geom::sew::{self, Face};
use crate::syntax::Span;

use super::features::Registry;
use super::value::{Data, Dim, Record, Value};
use super::Outcome;

/// The die model of `outcome`: its declarations that hold geometry, and its die face.
/// Declarations that failed (no value) are skipped: reporting them is the caller's job.
/// `registry` gives the colours of the feature kinds.
pub fn die_model(outcome: &Outcome, sources: &Sources, registry: &Registry) -> DieModel {
    let source_name = sources
        .get(outcome.file)
        .map_or_else(String::new, |f| f.name.clone());
    let trimmed = trimmed_panels(outcome);
    let mut model = DieModel {
        source_name,
        ..DieModel::default()
    };
    for d in &outcome.decls {
        let Some(value) = &d.value else { continue };
        if d.kind == "product" {
            product_faces(&d.name, value, &mut model.die_face.faces);
        }
        if let Data::Record(r) = &value.data {
            if let Some(f) = &r.feature {
                f.kind.die_face(&d.name, r, &mut model.die_face);
            }
        }
        if d.kind == "let" && matches!(&value.data, Data::Surface(s) if trimmed.contains(&&**s)) {
            continue;
        }
        let ctx = Ctx {
            sources,
            kind: &d.kind,
            color: registry.get(&d.kind).map_or_else(
                || {
                    if d.kind == "product" {
                        PRODUCT_COLOR
                    } else {
                        PLAIN_COLOR
                    }
                },
                |k| k.color(),
            ),
            decl_span: d.span,
            decl_line: sources.line(d.span),
        };
        if let Some(part) = ctx.part(d.name.clone(), value) {
            model.parts.push(part);
        }
    }
    model
}

/// The colour of products (grey-blue): the part the die is for.
const PRODUCT_COLOR: [f64; 3] = [0.45, 0.55, 0.70];

/// The untrimmed surfaces of the products trimmed at their outline: a `let` holding
/// one of them is the panel the product was cut from, and exporting it too would put
/// the untrimmed product back over the step draw.
fn trimmed_panels(outcome: &Outcome) -> Vec<&crate::geom::NurbsSurface> {
    let mut out = Vec::new();
    for d in outcome.decls.iter().filter(|d| d.kind == "product") {
        let Some(value) = &d.value else { continue };
        let items: Vec<&Value> = match &value.data {
            Data::List(items) => items.iter().collect(),
            _ => vec![value],
        };
        for v in items {
            if let Data::Trimmed(t) = &v.data {
                out.push(t.surface());
            }
        }
    }
    out
}

/// A product's faces of the die face: a trimmed surface, a surface, or a list of them
/// (nothing for any other value).
pub(crate) fn product_faces(name: &str, value: &Value, out: &mut Vec<Face>) {
    match &value.data {
        Data::Trimmed(t) => out.push(Face {
            name: name.to_string(),
            shape: sew::Shape::Trimmed((**t).clone()),
        }),
        Data::Surface(s) => out.push(Face {
            name: name.to_string(),
            shape: sew::Shape::Patch((**s).clone()),
        }),
        Data::List(items) => {
            for (i, item) in items.iter().enumerate() {
                product_faces(&format!("{name}/{i}"), item, out);
            }
        }
        _ => {}
    }
}

/// What every part of one declaration shares.
struct Ctx<'a> {
    sources: &'a Sources,
    kind: &'a str,
    color: [f64; 3],
    decl_span: Span,
    decl_line: usize,
}

impl Ctx<'_> {
    /// The part for `value` named `name`, or `None` when it holds no geometry.
    fn part(&self, name: String, value: &Value) -> Option<Part> {
        let mut part = Part {
            name,
            kind: self.kind.to_string(),
            color: self.color,
            line: self.line_of(value.span),
            shape: None,
            children: Vec::new(),
            line_bead: None,
            figures: Vec::new(),
        };
        match &value.data {
            Data::Surface(s) => part.shape = Some(Shape::Surface(s.clone())),
            Data::Trimmed(t) => part.shape = Some(Shape::Trimmed(t.clone())),
            Data::Mesh(m) => {
                // A mesh of shell elements (`quad_mesh`) says so, for the FE decks and
                // for reviewers; a triangle mesh keeps its declaration's kind.
                if part.kind == "let" && m.faces().iter().any(|f| f.is_quad()) {
                    part.kind = "quad_mesh".to_string();
                }
                part.shape = Some(Shape::Mesh(m.clone()))
            }
            Data::Curve3(c) => part.shape = Some(Shape::Curve(c.clone())),
            Data::Curve2(c) => {
                part.shape = Some(Shape::Curve(Arc::new(c.map_points(|p| p.extend(0.0)))))
            }
            Data::Sketch(s) => part.shape = Some(Shape::Curve(Arc::new(s.to_3d()))),
            Data::List(items) => {
                for (i, item) in items.iter().enumerate() {
                    if let Some(child) = self.part(format!("{}/{i}", part.name), item) {
                        part.children.push(child);
                    }
                }
            }
            Data::Record(r) => self.record_parts(&mut part, r),
            _ => return None,
        }
        if part.shape.is_none() && part.children.is_empty() {
            return None;
        }
        Some(part)
    }

    /// A record's geometric fields as children; for a feature, only the pieces its kind
    /// exports, with its line bead and quality figures.
    fn record_parts(&self, part: &mut Part, r: &Record) {
        if let Some(f) = &r.feature {
            part.line_bead = f.kind.line_bead(r);
            if let Some(Value {
                data: Data::Record(q),
                ..
            }) = r.get("quality")
            {
                figures(q, "", &mut part.figures);
            }
        }
        for (field, v) in &r.fields {
            if r.feature
                .as_ref()
                .is_some_and(|f| !f.kind.exports_field(field))
            {
                continue;
            }
            let piece = field.split_whitespace().collect::<Vec<_>>().join("-");
            if let Some(mut child) = self.part(format!("{}/{piece}", part.name), v) {
                if let Some(kind) = r.feature.as_ref().and_then(|f| f.kind.piece_kind(field)) {
                    child.kind = kind.to_string();
                }
                part.children.push(child);
            }
        }
    }

    /// The line of `span` when it lies in the declaration, else the declaration's line.
    fn line_of(&self, span: Span) -> usize {
        let d = self.decl_span;
        if span.file == d.file && span.start >= d.start && span.end <= d.end {
            self.sources.line(span)
        } else {
            self.decl_line
        }
    }
}

/// A feature's `quality` record flattened: `min_radius`, `front.draft`, ...
fn figures(r: &Record, prefix: &str, out: &mut Vec<Figure>) {
    for (name, v) in &r.fields {
        let name = format!("{prefix}{name}");
        let value = match &v.data {
            Data::Record(inner) => {
                figures(inner, &format!("{name}."), out);
                continue;
            }
            Data::Number(q) if q.dim == Dim::LENGTH => FigureValue::Length(q.value),
            Data::Number(q) if q.dim == Dim::ANGLE => FigureValue::Angle(q.value.to_degrees()),
            Data::Number(q) => FigureValue::Number(q.value),
            Data::Bool(b) => FigureValue::Flag(*b),
            Data::Tuple(items) => {
                let c: Vec<f64> = items
                    .iter()
                    .filter_map(|i| match &i.data {
                        Data::Number(q) => Some(q.value),
                        _ => None,
                    })
                    .collect();
                match c.as_slice() {
                    [x, y, z] => FigureValue::Point(DVec3::new(*x, *y, *z)),
                    _ => continue,
                }
            }
            _ => continue,
        };
        out.push(Figure { name, value });
    }
}
