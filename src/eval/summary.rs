//! A stable one-line summary of a value: what snapshot tests and `dieface check`
//! reviewers read. Floats are rounded to 6 decimals so platform noise never shows.

use glam::DVec3;

pub(crate) use crate::geom::curve::bounds;
use crate::geom::Point;

use super::units::display;
pub(crate) use super::units::round;
use super::value::{Data, Record, Value};

/// `kind name: summary` for a declaration, or `(failed)` when it has no value.
pub fn describe(value: Option<&Value>) -> String {
    match value {
        None => "(no value: failed or skipped)".into(),
        Some(v) => summarize(v),
    }
}

/// The summary of one value.
pub fn summarize(v: &Value) -> String {
    match &v.data {
        Data::Number(q) => format!("number {} ({})", display(*q), q.dim),
        Data::Bool(b) => format!("bool {b}"),
        // A long string is cut, so one line of `inspect` or `watch` stays a line.
        Data::Str(s) => format!("string {:?}", crate::diag::abridged(s, 60)),
        Data::List(items) => {
            let inner: Vec<String> = items.iter().take(4).map(summarize).collect();
            let more = if items.len() > 4 {
                format!(", ... ({} more)", items.len() - 4)
            } else {
                String::new()
            };
            format!("list of {} [{}{more}]", items.len(), inner.join(", "))
        }
        Data::Tuple(items) => {
            let inner: Vec<String> = items
                .iter()
                .map(|i| match &i.data {
                    Data::Number(q) => display(*q),
                    _ => summarize(i),
                })
                .collect();
            format!("({})", inner.join(", "))
        }
        Data::Record(r) if r.feature.is_some() => feature_summary(r),
        Data::Record(r) => {
            let fields: Vec<String> = r
                .fields
                .iter()
                .map(|(n, v)| format!("{n}: {}", summarize(v)))
                .collect();
            match &r.kind {
                Some(k) => format!("{k} {{ {} }}", fields.join("; ")),
                None => format!("{{ {} }}", fields.join("; ")),
            }
        }
        Data::Function(c) => format!("function {}({} parameters)", c.name, c.params.len()),
        Data::Builtin(b) => format!("builtin {}", b.signature()),
        Data::Module(m) => format!("module {:?} ({} members)", m.path, m.members.len()),
        Data::View(view) => format!("view {}", view.name()),
        Data::Sketch(s) => {
            let (lo, hi) = bounds(s.curve.control_points().iter().map(|p| p.to_3d()));
            let kinds: Vec<&str> = s.segments.iter().map(|g| g.kind).collect();
            format!(
                "sketch in {} view, {} segment{} [{}], {}, degree {}, {} control points{}, length {} mm, bounds {}",
                s.view.name(),
                s.segments.len(),
                if s.segments.len() == 1 { "" } else { "s" },
                kinds.join(" "),
                if s.closed { "closed" } else { "open" },
                s.curve.degree(),
                s.curve.control_points().len(),
                if s.curve.is_rational() { " (rational)" } else { "" },
                round(s.curve.length()),
                bbox(lo, hi)
            )
        }
        Data::Curve2(c) => format!(
            "2-D curve, degree {}, {} control points{}, length {} mm, bounds {}",
            c.degree(),
            c.control_points().len(),
            if c.is_rational() { " (rational)" } else { "" },
            round(c.length()),
            {
                let (lo, hi) = bounds(c.control_points().iter().map(|p| p.to_3d()));
                bbox(lo, hi)
            }
        ),
        Data::Curve3(c) => format!(
            "3-D curve, degree {}, {} control points{}, length {} mm, bounds {}",
            c.degree(),
            c.control_points().len(),
            if c.is_rational() { " (rational)" } else { "" },
            round(c.length()),
            {
                let (lo, hi) = bounds(sampled_curve(c));
                bbox(lo, hi)
            }
        ),
        Data::Surface(s) => {
            let (nu, nv) = s.counts();
            let (lo, hi) = bounds(sampled_surface(s));
            format!(
                "surface, degree {}x{}, {}x{} control points{}, bounds {}",
                s.degree_u(),
                s.degree_v(),
                nu,
                nv,
                if s.is_rational() { " (rational)" } else { "" },
                bbox(lo, hi)
            )
        }
        Data::Trimmed(t) => {
            let s = t.surface();
            let (nu, nv) = s.counts();
            let c = t.outer().curve();
            let (lo, hi) = bounds(sampled_curve(c));
            format!(
                "trimmed surface, degree {}x{}, {}x{} control points{}, outline length {} mm, bounds {}",
                s.degree_u(),
                s.degree_v(),
                nu,
                nv,
                if s.is_rational() { " (rational)" } else { "" },
                round(c.length()),
                bbox(lo, hi)
            )
        }
        Data::Mesh(m) => {
            let (t, q) = m.triangle_and_quad_counts();
            let b = m
                .bounding_box()
                .map_or("empty".to_string(), |(lo, hi)| bbox(lo, hi));
            format!(
                "mesh, {} vertices, {t} triangles, {q} quads, {} groups, bounds {b}",
                m.vertex_count(),
                m.groups().len()
            )
        }
        Data::Transform(t) => {
            let m = t.matrix().to_cols_array();
            let r: Vec<String> = m.iter().map(|v| format!("{}", round(*v))).collect();
            format!("transform [{}]", r.join(", "))
        }
    }
}

/// Bounds of the points of a curve sampled densely (tighter than the control polygon).
pub(crate) fn sampled_curve(c: &crate::geom::Curve3) -> impl Iterator<Item = DVec3> + '_ {
    let (a, b) = c.domain();
    (0..=256).map(move |i| c.point_at(a + (b - a) * i as f64 / 256.0))
}

/// Points of a surface sampled on a 33 x 33 grid, for its bounds.
pub(crate) fn sampled_surface(s: &crate::geom::NurbsSurface) -> impl Iterator<Item = DVec3> + '_ {
    let (u0, u1) = s.domain_u();
    let (v0, v1) = s.domain_v();
    (0..=32).flat_map(move |i| {
        (0..=32).map(move |j| {
            s.point_at(
                u0 + (u1 - u0) * i as f64 / 32.0,
                v0 + (v1 - v0) * j as f64 / 32.0,
            )
        })
    })
}

/// The total area (mm², rounded) and the bounds (as [`bbox`] writes them) of a
/// feature's patches: the extent a summary line gives.
pub(crate) fn patches_extent<'s>(
    surfaces: impl Iterator<Item = &'s crate::geom::NurbsSurface> + Clone,
) -> (f64, String) {
    let (lo, hi) = bounds(surfaces.clone().flat_map(sampled_surface));
    let area: f64 = surfaces.map(|s| s.area()).sum();
    (round(area), bbox(lo, hi))
}

/// Bounds as `(x, y, z)..(x, y, z)`, rounded.
pub(crate) fn bbox(lo: DVec3, hi: DVec3) -> String {
    let f = |p: DVec3| format!("({}, {}, {})", round(p.x), round(p.y), round(p.z));
    format!("{}..{}", f(lo), f(hi))
}

/// One line for a feature: its pieces and its worst quality figures, as its kind says.
fn feature_summary(r: &Record) -> String {
    r.feature
        .as_ref()
        .map_or_else(String::new, |f| f.kind.summary(r))
}

/// The quality report of a feature, one line per figure group (empty for other values):
/// what `dieface inspect` prints under the feature's line.
pub fn feature_report(v: &Value) -> Vec<String> {
    let Data::Record(r) = &v.data else {
        return Vec::new();
    };
    let Some(quality) = r.get("quality") else {
        return Vec::new();
    };
    if r.feature.is_none() {
        return Vec::new();
    }
    let Data::Record(q) = &quality.data else {
        return Vec::new();
    };
    let mut lines = Vec::new();
    let mut overall = Vec::new();
    for (name, value) in &q.fields {
        match &value.data {
            Data::Record(inner) => {
                let figures: Vec<String> = inner
                    .fields
                    .iter()
                    .map(|(n, v)| format!("{n} {}", figure(v)))
                    .collect();
                lines.push(format!("{name}: {}", figures.join(", ")));
            }
            _ => overall.push(format!("{name} {}", figure(value))),
        }
    }
    lines.insert(0, format!("worst: {}", overall.join(", ")));
    lines
}

/// A figure as `12.5 mm`, `0.01 deg`, `3`, `yes`, a point as `(1 mm, 2 mm, 3 mm)`.
fn figure(v: &Value) -> String {
    match &v.data {
        Data::Number(q) => super::units::display(*q),
        Data::Bool(b) => if *b { "yes" } else { "no" }.to_string(),
        _ => summarize(v),
    }
}
