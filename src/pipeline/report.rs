//! What `inspect` reports of an evaluation: one line per declaration (text), or the
//! full evaluated data as JSON in the schema of `docs/inspect-json.md` (keys in a fixed
//! order, floats with full precision). Pure functions of the outcome: `cli` prints them,
//! the viewer can serve them.

use std::collections::HashMap;
use std::time::Duration;

use glam::DVec3;
use serde::ser::{SerializeMap, SerializeSeq};
use serde::{Serialize, Serializer};
use serde_json::{json, Map, Value as Json};

use crate::diag::Sources;
use crate::eval::sketch::View;
use crate::eval::summary::{describe, feature_report};
use crate::eval::units::round;
use crate::eval::value::{Data, Dim, Quantity, Value};
use crate::eval::Outcome;
use crate::geom::{NurbsCurve, NurbsSurface, Point};

/// The version of the JSON schema (`docs/inspect-json.md`); bumped on any change that
/// could break a reader.
pub const SCHEMA: u32 = 1;

/// How long each declaration took to evaluate (`Engine::last_timings`).
pub type Timings<'a> = &'a [(String, Duration)];

/// Each declaration's time by name, looked up once per declaration (a search of the
/// list for each would grow with the square of the declarations).
fn timing_index<'a>(timings: Timings<'a>) -> HashMap<&'a str, Duration> {
    timings.iter().map(|(n, t)| (n.as_str(), *t)).collect()
}

/// The text report: per declaration `kind name (line N, 1.2 ms): summary`, with the
/// area of surfaces and meshes, then a feature's quality report indented under it.
pub fn inspect_lines(outcome: &Outcome, sources: &Sources, timings: Timings) -> Vec<String> {
    let mut out = Vec::new();
    let timings = timing_index(timings);
    for d in &outcome.decls {
        let line = sources.line(d.span);
        let time = timings.get(d.name.as_str()).map_or(String::new(), |t| {
            format!(", {:.1} ms", t.as_secs_f64() * 1e3)
        });
        let mut summary = describe(d.value.as_ref());
        if let Some(a) = d.value.as_ref().and_then(area) {
            summary.push_str(&format!(", area {} mm²", round(a)));
        }
        out.push(format!(
            "{} {} (line {line}{time}): {summary}",
            d.kind, d.name
        ));
        if let Some(v) = &d.value {
            for l in feature_report(v) {
                out.push(format!("    {l}"));
            }
        }
    }
    out
}

/// The JSON report (`docs/inspect-json.md`): the file, every declaration with its
/// value, and the diagnostics.
pub fn inspect_json<'a>(
    outcome: &'a Outcome,
    sources: &'a Sources,
    timings: Timings<'a>,
) -> InspectJson<'a> {
    InspectJson {
        outcome,
        sources,
        timings: timing_index(timings),
    }
}

/// The JSON report, written as it is serialized: a declaration's value (a list of a
/// million records, say) goes straight to the writer instead of first becoming a tree
/// of JSON nodes several times its size. The same bytes as a tree would give.
pub struct InspectJson<'a> {
    outcome: &'a Outcome,
    sources: &'a Sources,
    timings: HashMap<&'a str, Duration>,
}

impl Serialize for InspectJson<'_> {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        let (outcome, sources) = (self.outcome, self.sources);
        let decls: Vec<DeclJson> = outcome
            .decls
            .iter()
            .map(|d| DeclJson {
                decl: d,
                sources,
                eval_ms: self
                    .timings
                    .get(d.name.as_str())
                    .map(|t| t.as_secs_f64() * 1e3),
            })
            .collect();
        let diagnostics: Vec<Json> = outcome
            .diagnostics
            .iter()
            .map(|d| {
                let (line, column) = sources.line_col(d.primary.span);
                let mut m = Map::new();
                m.insert("code".into(), json!(d.code));
                m.insert("message".into(), json!(d.message));
                m.insert(
                    "file".into(),
                    json!(sources
                        .get(d.primary.span.file)
                        .map_or("", |f| f.name.as_str())),
                );
                m.insert("line".into(), json!(line));
                m.insert("column".into(), json!(column));
                m.insert("help".into(), json!(d.help));
                Json::Object(m)
            })
            .collect();
        let mut top = serializer.serialize_map(Some(4))?;
        top.serialize_entry("schema", &SCHEMA)?;
        top.serialize_entry(
            "file",
            sources.get(outcome.file).map_or("", |f| f.name.as_str()),
        )?;
        top.serialize_entry("declarations", &decls)?;
        top.serialize_entry("diagnostics", &diagnostics)?;
        top.end()
    }
}

/// One declaration of [`InspectJson`].
struct DeclJson<'a> {
    decl: &'a crate::eval::DeclResult,
    sources: &'a Sources,
    eval_ms: Option<f64>,
}

impl Serialize for DeclJson<'_> {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        let d = self.decl;
        let (line, column) = self.sources.line_col(d.span);
        let mut m = serializer.serialize_map(Some(7))?;
        m.serialize_entry("name", &d.name)?;
        m.serialize_entry("kind", &d.kind)?;
        m.serialize_entry("line", &line)?;
        m.serialize_entry("column", &column)?;
        m.serialize_entry("type", &d.value.as_ref().map(type_token))?;
        m.serialize_entry("eval_ms", &self.eval_ms)?;
        m.serialize_entry(
            "value",
            &d.value.as_ref().map(|v| ValueJson {
                value: v,
                sources: self.sources,
            }),
        )?;
        m.end()
    }
}

/// A value as JSON ([`value_json`]), lists, tuples and records written item by item.
struct ValueJson<'a> {
    value: &'a Value,
    sources: &'a Sources,
}

impl Serialize for ValueJson<'_> {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        let v = self.value;
        let item = |value| ValueJson {
            value,
            sources: self.sources,
        };
        match &v.data {
            Data::List(items) | Data::Tuple(items) if as_point(v).is_none() => {
                let mut seq = serializer.serialize_seq(Some(items.len()))?;
                for i in items.iter() {
                    seq.serialize_element(&item(i))?;
                }
                seq.end()
            }
            Data::Record(r) => {
                struct Fields<'b>(&'b [(String, Value)], &'b Sources);
                impl Serialize for Fields<'_> {
                    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
                        let mut m = s.serialize_map(Some(self.0.len()))?;
                        for (n, f) in self.0 {
                            m.serialize_entry(
                                n,
                                &ValueJson {
                                    value: f,
                                    sources: self.1,
                                },
                            )?;
                        }
                        m.end()
                    }
                }
                let mut m = serializer.serialize_map(Some(2))?;
                m.serialize_entry("kind", &r.kind)?;
                m.serialize_entry("fields", &Fields(&r.fields, self.sources))?;
                m.end()
            }
            _ => value_json(v, self.sources).serialize(serializer),
        }
    }
}

/// The area of a surface or a mesh.
fn area(v: &Value) -> Option<f64> {
    match &v.data {
        Data::Surface(s) => Some(s.area()),
        Data::Trimmed(t) => Some(t.area()),
        Data::Mesh(m) => Some(m.total_area()),
        _ => None,
    }
}

/// A short, stable type token (`length`, `surface`, ...) for the JSON `type` field.
fn type_token(v: &Value) -> &'static str {
    match &v.data {
        Data::Number(q) if q.bare && q.dim.is_none() => "number",
        Data::Number(q) => match q.dim {
            Dim::LENGTH => "length",
            Dim::ANGLE => "angle",
            d if d.is_none() => "ratio",
            _ => "quantity",
        },
        Data::Bool(_) => "bool",
        Data::Str(_) => "string",
        Data::List(_) => "list",
        Data::Tuple(_) if as_point(v).is_some() => "point",
        Data::Tuple(_) => "tuple",
        Data::Record(_) => "record",
        Data::Function(_) | Data::Builtin(_) => "function",
        Data::Module(_) => "module",
        Data::View(_) => "view",
        Data::Sketch(_) => "sketch",
        Data::Curve2(_) => "curve2",
        Data::Curve3(_) => "curve3",
        Data::Surface(_) => "surface",
        Data::Trimmed(_) => "trimmed_surface",
        Data::Mesh(_) => "mesh",
        Data::Transform(_) => "transform",
    }
}

/// A 2- or 3-tuple of lengths or plain numbers, as its coordinates (mm).
fn as_point(v: &Value) -> Option<Vec<f64>> {
    let Data::Tuple(items) = &v.data else {
        return None;
    };
    if !(2..=3).contains(&items.len()) {
        return None;
    }
    items
        .iter()
        .map(|i| match i.data {
            Data::Number(q) if q.dim == Dim::LENGTH || (q.bare && q.dim.is_none()) => Some(q.value),
            _ => None,
        })
        .collect()
}

/// `{value, unit, bare}`: lengths in mm, angles in degrees, plain numbers and ratios
/// as they are, other dimensions in base units (`mm^2`, `mm*rad^-1`, ...).
fn number_json(q: Quantity) -> Json {
    let (value, unit) = match q.dim {
        Dim::LENGTH => (q.value, "mm".to_string()),
        Dim::ANGLE => (q.value.to_degrees(), "deg".to_string()),
        d if d.is_none() => (q.value, String::new()),
        d => {
            let power = |name: &str, p: i8| match p {
                0 => None,
                1 => Some(name.to_string()),
                p => Some(format!("{name}^{p}")),
            };
            let parts: Vec<String> = [power("mm", d.length), power("rad", d.angle)]
                .into_iter()
                .flatten()
                .collect();
            (q.value, parts.join("*"))
        }
    };
    let mut m = Map::new();
    m.insert("value".into(), json!(value));
    m.insert("unit".into(), json!(unit));
    m.insert("bare".into(), json!(q.bare));
    Json::Object(m)
}

fn point_json(p: DVec3, dim: usize) -> Json {
    let c = [p.x, p.y, p.z];
    json!(c[..dim])
}

fn bounds_json(lo: DVec3, hi: DVec3) -> Json {
    let mut m = Map::new();
    m.insert("min".into(), point_json(lo, 3));
    m.insert("max".into(), point_json(hi, 3));
    Json::Object(m)
}

fn curve_json<P: Point>(c: &NurbsCurve<P>) -> Json {
    let mut m = Map::new();
    m.insert("dimension".into(), json!(P::DIM));
    m.insert("degree".into(), json!(c.degree()));
    m.insert("knots".into(), json!(c.knots().as_slice()));
    m.insert(
        "weights".into(),
        c.weights().map_or(Json::Null, |w| json!(w)),
    );
    m.insert(
        "control_points".into(),
        Json::Array(
            c.control_points()
                .iter()
                .map(|p| point_json(p.to_3d(), P::DIM))
                .collect(),
        ),
    );
    Json::Object(m)
}

fn surface_json(s: &NurbsSurface) -> Json {
    let (nu, nv) = s.counts();
    let rows = |f: &dyn Fn(usize, usize) -> Json| -> Json {
        Json::Array(
            (0..nu)
                .map(|i| Json::Array((0..nv).map(|j| f(i, j)).collect()))
                .collect(),
        )
    };
    let mut m = Map::new();
    m.insert("degree_u".into(), json!(s.degree_u()));
    m.insert("degree_v".into(), json!(s.degree_v()));
    m.insert("knots_u".into(), json!(s.knots_u().as_slice()));
    m.insert("knots_v".into(), json!(s.knots_v().as_slice()));
    m.insert(
        "weights".into(),
        if s.is_rational() {
            rows(&|i, j| json!(s.weight(i, j)))
        } else {
            Json::Null
        },
    );
    m.insert(
        "control_points".into(),
        rows(&|i, j| point_json(s.control_point(i, j), 3)),
    );
    Json::Object(m)
}

fn view_plane(view: &View) -> Json {
    match view {
        View::Section { a, b } => {
            let mut m = Map::new();
            m.insert("a".into(), json!([a.x, a.y]));
            m.insert("b".into(), json!([b.x, b.y]));
            Json::Object(m)
        }
        _ => Json::Null,
    }
}

/// The JSON encoding of a value (`docs/inspect-json.md`).
fn value_json(v: &Value, sources: &Sources) -> Json {
    if let Some(p) = as_point(v) {
        return json!(p);
    }
    match &v.data {
        Data::Number(q) => number_json(*q),
        Data::Bool(b) => json!(b),
        Data::Str(s) => json!(s.as_ref()),
        Data::List(items) | Data::Tuple(items) => {
            Json::Array(items.iter().map(|i| value_json(i, sources)).collect())
        }
        Data::Record(r) => {
            let mut fields = Map::new();
            for (n, f) in &r.fields {
                fields.insert(n.clone(), value_json(f, sources));
            }
            let mut m = Map::new();
            m.insert("kind".into(), json!(r.kind));
            m.insert("fields".into(), Json::Object(fields));
            Json::Object(m)
        }
        Data::Function(c) => {
            let mut m = Map::new();
            m.insert("function".into(), json!(c.name));
            m.insert(
                "parameters".into(),
                json!(c
                    .params
                    .iter()
                    .map(|p| p.name.node.as_str())
                    .collect::<Vec<_>>()),
            );
            Json::Object(m)
        }
        Data::Builtin(b) => {
            let mut m = Map::new();
            m.insert("function".into(), json!(b.name));
            m.insert(
                "parameters".into(),
                json!(b.params.iter().map(|p| p.name).collect::<Vec<_>>()),
            );
            Json::Object(m)
        }
        Data::Module(md) => {
            let mut m = Map::new();
            m.insert("module".into(), json!(md.path));
            m.insert(
                "members".into(),
                json!(md
                    .members
                    .iter()
                    .map(|(n, _)| n.as_str())
                    .collect::<Vec<_>>()),
            );
            Json::Object(m)
        }
        Data::View(view) => {
            let mut m = Map::new();
            m.insert("view".into(), json!(view.name()));
            m.insert("plane".into(), view_plane(view));
            Json::Object(m)
        }
        Data::Sketch(s) => {
            let segments: Vec<Json> = s
                .segments
                .iter()
                .map(|g| {
                    let mut m = Map::new();
                    m.insert("kind".into(), json!(g.kind));
                    m.insert("line".into(), json!(sources.line(g.span)));
                    m.insert("range".into(), json!([g.range.0, g.range.1]));
                    Json::Object(m)
                })
                .collect();
            let mut m = Map::new();
            m.insert("view".into(), json!(s.view.name()));
            m.insert("plane".into(), view_plane(&s.view));
            m.insert("closed".into(), json!(s.closed));
            m.insert("segments".into(), Json::Array(segments));
            m.insert("curve".into(), curve_json(&s.curve));
            Json::Object(m)
        }
        Data::Curve2(c) => curve_json(c.as_ref()),
        Data::Curve3(c) => curve_json(c.as_ref()),
        Data::Surface(s) => surface_json(s),
        Data::Trimmed(t) => {
            let mut m = Map::new();
            m.insert("surface".into(), surface_json(t.surface()));
            m.insert("outer".into(), curve_json(t.outer().curve()));
            m.insert("area".into(), json!(t.area()));
            Json::Object(m)
        }
        Data::Mesh(mesh) => {
            let (t, q) = mesh.triangle_and_quad_counts();
            let groups: Vec<Json> = mesh
                .groups()
                .iter()
                .map(|g| {
                    let mut m = Map::new();
                    m.insert("name".into(), json!(g.name()));
                    m.insert("faces".into(), json!(g.faces().len()));
                    Json::Object(m)
                })
                .collect();
            let mut m = Map::new();
            m.insert("vertices".into(), json!(mesh.vertex_count()));
            m.insert("triangles".into(), json!(t));
            m.insert("quads".into(), json!(q));
            m.insert("groups".into(), Json::Array(groups));
            m.insert(
                "bounds".into(),
                mesh.bounding_box()
                    .map_or(Json::Null, |(lo, hi)| bounds_json(lo, hi)),
            );
            Json::Object(m)
        }
        Data::Transform(t) => {
            let mut m = Map::new();
            m.insert("matrix".into(), json!(t.matrix().to_cols_array()));
            Json::Object(m)
        }
    }
}
