//! `step_draw name { ... }`: the block's fields read into [`crate::die::step_draw`]'s
//! input, and its result into a record.
//!
//! ```text
//! import "std/addendum" as add
//! step_draw addendum {
//!     product = outline               // the product outline (G_D), a 3-D cubic curve
//!     opening = opening               // the punch_opening (or a 3-D curve): G_U
//!     tolerance = 0.01 mm             // profile ends, fits (default 0.01 mm)
//!     closed = true                   // default: when both guides are closed
//!     section front {                 // key sections, in order along the outline
//!         at = ((0, -300), (0, -520)) // two top-view points: the vertical plane
//!         profile = add.wall          // a function (product, opening) -> sketch, or a
//!     }                               // sketch drawn in the section plane
//! }
//! ```
//!
//! A profile function gets the section plane's two guide points as `(s, z)` tuples,
//! `s` from the first `at` point towards the second: where the plane meets the product
//! outline, then where it meets the punch opening; it returns the profile between them.
//! A drawn sketch must start and end within `tolerance` of those points.

use std::sync::Arc;

use glam::DVec2;

use crate::diag::Diagnostic;
use crate::die::step_draw::{self as sd, Guides, Options, Problem, SectionEnds, SectionSpec};
use crate::geom::{Curve2, Curve3};
use crate::syntax::Span;

use super::super::builtins::{as_point2, type_error};
use super::super::sketch::{Sketch, View};
use super::super::summary::patches_extent;
use super::super::value::{Data, Record, Value};
use super::explain::{diagnostic, Blame, Explanation};
use super::kind::{FeatureKind, FieldNames};
use super::{check_record, feature_error, feature_value, join_figures, mm, record, show, Block};
use crate::die::model::DieFace;
use crate::geom::sew::{Face, Shape};

/// A key section as written, with what the diagnostics need to point at it.
struct SectionSource {
    name: String,
    /// The section's name in `section front`.
    name_span: Span,
    /// The value of `at`.
    at: Span,
    /// The value of `profile`.
    profile: Span,
    /// The two `at` points.
    a: DVec2,
    b: DVec2,
    /// Where the plane meets the guides.
    ends: SectionEnds,
    /// The profile in the plane's (s, z).
    curve: Curve2,
    /// The profile as a sketch (drawn directly or returned by the profile function).
    sketch: Option<Arc<Sketch>>,
    /// The profile function's name, when the profile is a function.
    function: Option<String>,
}

/// Builds the step draw of `block`.
fn build(block: &Block) -> Result<Value, Diagnostic> {
    let units = block.units;
    let product_field = block.get("product").ok_or_else(|| {
        block.missing(
            "product",
            "give the product outline: `product = boundary(panel)` or `project(trim, panel)`",
        )
    })?;
    let product = product_curve(&product_field.value)?;
    let opening_field = block.get("opening").ok_or_else(|| {
        block.missing(
            "opening",
            "give the punch opening: `opening = my_opening` (a punch_opening)",
        )
    })?;
    let opening = opening_line(&opening_field.value)?;
    let tolerance = block.length_or("tolerance", 0.01)?;
    if !(tolerance.is_finite() && tolerance > 0.0) {
        let span = block.get("tolerance").map_or(block.span, |f| f.value.span);
        return Err(feature_error(
            KIND,
            "the tolerance of a step draw must be a positive length",
            span,
            "not positive",
            "the tolerance is how far a drawn profile's ends may lie from the guides and how closely the surfaces follow the profiles: 0.01 mm (the default) is die-face practice",
        ));
    }
    let both_closed = product.is_closed() && opening.is_closed();
    let closed = match block.get("closed") {
        Some(f) => match &f.value.data {
            Data::Bool(true) if !both_closed => {
                return Err(not_closed(&product, &opening, f.value.span))
            }
            Data::Bool(b) => *b,
            _ => {
                return Err(type_error(
                    &f.value,
                    "`closed` of a step draw",
                    "true or false",
                ))
            }
        },
        None => both_closed,
    };
    if product.degree() != 3 || product.is_rational() {
        return Err(diagnostic(KIND, block, not_cubic(&product), |_| None));
    }
    let binder = match block.get("binder") {
        Some(f) => binder_patches(&f.value)?,
        None => Vec::new(),
    };
    let tangent_product = flag(block, "tangent_product")?;
    let tangent_binder = flag(block, "tangent_binder")?;
    let guides = sd::oriented(Guides {
        product,
        opening,
        product_surface: match &product_field.value.data {
            Data::Trimmed(t) => Some(t.surface().clone()),
            _ => None,
        },
        binder,
        closed,
    });

    let mut sources = Vec::new();
    for (name, field) in block.named("section") {
        let what = format!("`section {name}`");
        let r = record(
            &field.value,
            &what,
            "a block such as `section front { at = ((0, -300), (0, -520)); profile = add.wall }`",
        )?;
        check_record(r, field.value.span, &what, &["at", "profile"])?;
        let at_value = r.get("at").ok_or_else(|| {
            field.missing(&what, "at", "place the section with two top-view points, `at = ((x1, y1), (x2, y2))`: the first inside the product outline, the second beyond the punch opening; the vertical plane through them is the section")
        })?;
        let (a, b) = two_points(at_value, units, &what)?;
        let profile_value = r.get("profile").ok_or_else(|| {
            field.missing(&what, "profile", format!(
                "give the profile from the product outline to the punch opening: a profile function such as `profile = add.wall` (it is handed both points), or a sketch in the section plane, `sketch(section({}, {})) {{ ... }}`",
                p2(a),
                p2(b)
            ))
        })?;
        if let Data::Sketch(s) = &profile_value.data {
            check_view(s, profile_value.span, name, a, b, None)?;
        }
        let ends = sd::section_ends(&guides, a, b).map_err(|p| match p {
            Problem::MissesGuide { product } => {
                let x = misses_guide(&guides, product, name, sources.len(), a, b);
                diagnostic(KIND, block, x, |_| Some(at_value.span))
            }
            p => feature_error(
                KIND,
                format!("the plane of section `{name}` cannot be cut with the guides: {p}"),
                at_value.span,
                "this section plane",
                "place the section with two different top-view points across the addendum: the first inside the product outline, the second beyond the punch opening",
            ),
        })?;
        let (curve, sketch, function) = match &profile_value.data {
            Data::Function(_) | Data::Builtin(_) => {
                let function = function_name(profile_value);
                let args = vec![
                    Value::point2(ends.product, profile_value.span),
                    Value::point2(ends.opening, profile_value.span),
                ];
                let out = (block.apply)(profile_value, args, profile_value.span).map_err(|d| {
                    in_profile_call(d, &function, name, profile_value.span, &ends)
                })?;
                match &out.data {
                    Data::Sketch(s) => {
                        check_view(s, profile_value.span, name, a, b, Some(&function))?;
                        (s.curve.clone(), Some(s.clone()), Some(function))
                    }
                    Data::Curve2(c) => ((**c).clone(), None, Some(function)),
                    _ => {
                        return Err(function_returns(
                            &out,
                            &function,
                            name,
                            profile_value.span,
                        ))
                    }
                }
            }
            Data::Sketch(s) => (s.curve.clone(), Some(s.clone()), None),
            Data::Curve2(c) => ((**c).clone(), None, None),
            _ => {
                return Err(type_error(
                    profile_value,
                    &format!("`profile` of {what}"),
                    "a profile sketch drawn in the section plane (`sketch(section(a, b)) { ... }`), or a profile function such as `add.wall`",
                ))
            }
        };
        sources.push(SectionSource {
            name: name.to_string(),
            name_span: field.name_word(),
            at: at_value.span,
            profile: profile_value.span,
            a,
            b,
            ends,
            curve,
            sketch,
            function,
        });
    }
    let specs: Vec<SectionSpec> = sources
        .iter()
        .map(|s| SectionSpec {
            name: s.name.clone(),
            a: s.a,
            b: s.b,
            profile: s.curve.clone(),
        })
        .collect();
    let options = Options {
        tolerance,
        tangent_product,
        tangent_binder,
    };
    let result = sd::build(&guides, &specs, &options).map_err(|e| {
        Context {
            block,
            guides: &guides,
            sections: &sources,
            tolerance,
        }
        .diagnose(e.section, &e.problem)
    })?;
    output(block, result)
}

/// The binder's patches from the `binder` field: the step draw meets them tangentially
/// across the punch opening line.
fn binder_patches(v: &Value) -> Result<Vec<crate::geom::NurbsSurface>, Diagnostic> {
    match &v.data {
        Data::Record(r) => match r
            .feature
            .as_ref()
            .and_then(|f| f.model::<crate::die::blankholder::Blankholder>())
        {
            Some(b) => Ok(b.patches.iter().map(|p| p.surface.clone()).collect()),
            _ => Err(type_error(
                v,
                "`binder` of a step draw",
                "a blankholder (the name of a `blankholder` declaration)",
            )),
        },
        _ => Err(type_error(
            v,
            "`binder` of a step draw",
            "a blankholder (the name of a `blankholder` declaration)",
        )),
    }
}

/// A true/false field that defaults to true.
fn flag(block: &Block, name: &str) -> Result<bool, Diagnostic> {
    match block.get(name) {
        None => Ok(true),
        Some(f) => match &f.value.data {
            Data::Bool(b) => Ok(*b),
            _ => Err(type_error(
                &f.value,
                &format!("`{name}` of a step draw"),
                "true or false",
            )),
        },
    }
}

/// The product outline of the `product` field: a 3-D curve (a drawing has no heights),
/// or a trimmed product, whose outer loop is the outline.
fn product_curve(v: &Value) -> Result<Curve3, Diagnostic> {
    match &v.data {
        Data::Curve3(c) => Ok((**c).clone()),
        Data::Trimmed(t) => Ok(t.outer().curve().clone()),
        Data::Sketch(_) | Data::Curve2(_) => Err(Diagnostic::new(
            "die::type_mismatch",
            format!(
                "`product` of a step draw must be the product outline in 3-D, but this is {}, without the product's heights",
                drawing(v)
            ),
            v.span,
            format!("this is {}", drawing(v)),
        )
        .with_help("project the trim line onto the product: `product = project(trim, panel)`")),
        _ => Err(type_error(
            v,
            "`product` of a step draw",
            "the product outline, a 3-D curve such as `project(trim, panel)`, or the trimmed product, `trim(panel, outline)`",
        )),
    }
}

/// The punch opening line of the `opening` field: a punch opening's closed line, or a
/// 3-D curve (a drawing has no heights).
fn opening_line(v: &Value) -> Result<Curve3, Diagnostic> {
    const EXPECTED: &str =
        "a punch opening (the name of a `punch_opening` declaration) or a 3-D curve";
    match &v.data {
        Data::Record(r) => match r.feature.as_ref().and_then(|f| f.model::<crate::die::punch_opening::PunchOpening>()) {
            Some(p) => Ok(p.line.clone()),
            _ => Err(type_error(v, "`opening` of a step draw", EXPECTED)),
        },
        Data::Curve3(c) => Ok((**c).clone()),
        Data::Sketch(_) | Data::Curve2(_) => Err(Diagnostic::new(
            "die::type_mismatch",
            format!(
                "`opening` of a step draw must be the punch opening, but this is {}, without the binder's heights",
                drawing(v)
            ),
            v.span,
            format!("this is {}", drawing(v)),
        )
        .with_help("pass the punch opening built from the drawing (the name of its `punch_opening` declaration), or a 3-D curve")),
        _ => Err(type_error(v, "`opening` of a step draw", EXPECTED)),
    }
}

/// "a sketch in the top view", "a 2-D curve".
fn drawing(v: &Value) -> String {
    match &v.data {
        Data::Sketch(s) => format!("a sketch in the {} view", view_name(&s.view)),
        _ => v.type_name(),
    }
}

/// A view as scripts write it.
fn view_name(view: &View) -> String {
    match view {
        View::Section { a, b } => format!("section({}, {})", p2(*a), p2(*b)),
        v => v.name().to_string(),
    }
}

/// `closed = true` on guides that are not both closed.
fn not_closed(product: &Curve3, opening: &Curve3, span: Span) -> Diagnostic {
    let gap = |c: &Curve3| num(c.start_point().distance(c.end_point()));
    let which = match (product.is_closed(), opening.is_closed()) {
        (false, false) => format!(
            "both guides are open: the product outline's ends are {} mm apart, the punch opening line's {} mm",
            gap(product),
            gap(opening)
        ),
        (false, true) => format!(
            "the product outline is open: its ends are {} mm apart",
            gap(product)
        ),
        _ => format!(
            "the punch opening line is open: its ends are {} mm apart",
            gap(opening)
        ),
    };
    feature_error(
        KIND,
        format!("`closed = true`, but {which}"),
        span,
        "asks for a step draw all the way round",
        "a closed step draw goes all the way round and needs a closed product outline and a closed punch opening; for a step draw along part of the outline set `closed = false`, or leave `closed` out (it follows the guides)",
    )
}

/// A product outline that is not a non-rational cubic.
fn not_cubic(product: &Curve3) -> Explanation<Part> {
    let what = match (product.degree(), product.is_rational()) {
        (1, _) => "a polyline (degree 1)".to_string(),
        (2, true) => "a curve of exact arcs (degree 2, rational)".to_string(),
        (d, true) => format!("a rational curve of degree {d}"),
        (d, false) => format!("a curve of degree {d}"),
    };
    Explanation::new(
        format!("the product outline must be a cubic B-spline (degree 3, not rational), but this is {what}"),
        Blame::Field("product"),
        "this outline",
        "the step draw's product edge takes the outline's own control points, so it must be a cubic: project the trim line onto the product with `project(trim, panel)`, or fit a cubic through points of it with `interpolate(points)` (degree 3 by default)",
    )
}

/// `at = (a, b)`: two top-view points.
fn two_points(
    v: &Value,
    units: super::super::units::Units,
    what: &str,
) -> Result<(DVec2, DVec2), Diagnostic> {
    let at_what = format!("`at` of {what}");
    let expected = "two top-view points `((x1, y1), (x2, y2))`";
    let Data::Tuple(items) = &v.data else {
        return Err(type_error(v, &at_what, expected));
    };
    if items.len() != 2 {
        return Err(type_error(v, &at_what, expected));
    }
    if items.iter().all(|i| matches!(i.data, Data::Number(_))) {
        return Err(feature_error(
            KIND,
            format!("{at_what} is one point, but a section plane needs two"),
            v.span,
            "one top-view point",
            "give two top-view points, `at = ((x1, y1), (x2, y2))`: the vertical section plane runs through both, from inside the product outline to beyond the punch opening",
        ));
    }
    let a = as_point2(&items[0], units, &at_what)?;
    let b = as_point2(&items[1], units, &at_what)?;
    if a.distance(b) < 1e-6 {
        return Err(feature_error(
            KIND,
            format!("{at_what} gives the same point twice, but a section plane needs two different points"),
            v.span,
            format!("{} twice", p2(a)),
            "the section plane runs vertically through two different top-view points: the first inside the product outline, the second beyond the punch opening",
        ));
    }
    Ok((a, b))
}

/// A profile sketch must be drawn across the section, not in the top view.
fn check_view(
    s: &Sketch,
    span: Span,
    name: &str,
    a: DVec2,
    b: DVec2,
    function: Option<&str>,
) -> Result<(), Diagnostic> {
    if s.view != View::Top {
        return Ok(());
    }
    let label = match function {
        Some(f) => format!("`{f}` returns a top-view sketch"),
        None => "a top-view sketch".to_string(),
    };
    Err(feature_error(
        KIND,
        format!("the profile of section `{name}` is drawn in the top view, but a profile is drawn in its section plane"),
        span,
        label,
        format!(
            "draw the profile across the section, s from the first `at` point and z up: `sketch(section({}, {})) {{ ... }}` or `sketch(profile) {{ ... }}`; or give a profile function such as `add.wall`",
            p2(a),
            p2(b)
        ),
    ))
}

/// The name of a profile function value.
fn function_name(v: &Value) -> String {
    match &v.data {
        Data::Function(c) => c.name.clone(),
        Data::Builtin(b) => b.name.to_string(),
        _ => "the profile function".to_string(),
    }
}

/// A failure inside (or in calling) the profile function of section `name`: the call is
/// shown as this section's, with the two points it was given.
fn in_profile_call(
    mut d: Diagnostic,
    function: &str,
    name: &str,
    span: Span,
    ends: &SectionEnds,
) -> Diagnostic {
    let points = format!("product {}, opening {}", p2(ends.product), p2(ends.opening));
    if d.primary.span == span {
        // The call itself failed: its arguments.
        let param = d
            .primary
            .message
            .strip_suffix("` is missing")
            .and_then(|m| m.strip_prefix('`'))
            .map(str::to_string);
        let base = format!("a step draw calls a profile function with the section's two points only, `(s, z)` each: for section `{name}`, {points}");
        let help = match (d.code, param) {
            ("die::missing_argument", Some(param)) => format!(
                "{base}; set `{param}` in a function of your own that calls `{function}`: `fn my_profile(product, opening) = {function}(product, opening, {param}: ...)` (through its module when imported, e.g. `add.{function}`)"
            ),
            ("die::missing_argument" | "die::too_many_arguments", _) => {
                format!("{base}: define it as `fn {function}(product, opening) = ...`")
            }
            _ => return d,
        };
        d.help = Some(help);
        return d;
    }
    let context = format!("in this call of `{function}` for section `{name}`: {points}");
    match d.secondary.iter_mut().find(|l| l.span == span) {
        Some(l) => l.message = context,
        None => d = d.with_label(span, context),
    }
    d
}

/// A profile function that returned something other than a profile.
fn function_returns(out: &Value, function: &str, name: &str, span: Span) -> Diagnostic {
    feature_error(
        KIND,
        format!(
            "the profile function `{function}` of section `{name}` returns {}, not a profile",
            out.type_name()
        ),
        span,
        format!("`{function}` returns {} here", out.type_name()),
        "a profile function takes the section's product and opening points `(s, z)` and returns the profile between them, drawn as `sketch(profile) { from product ... line to opening }`; `std/addendum` has `wall`, `step` and `flat_binder`",
    )
}

/// The plane of section `name` (the `k`th, through `a` and `b`) misses a guide.
fn misses_guide(
    guides: &Guides,
    product: bool,
    name: &str,
    k: usize,
    a: DVec2,
    b: DVec2,
) -> Explanation<Part> {
    let (curve, what) = if product {
        (&guides.product, "product outline")
    } else {
        (&guides.opening, "punch opening line")
    };
    let (lo, hi) = top_bounds(curve);
    let ends = if guides.closed {
        ""
    } else {
        " between the guides' ends"
    };
    Explanation::new(
        format!("the plane of section `{name}` does not cross the {what}"),
        Part::At(k),
        format!(
            "the vertical plane through {} and {} misses the {what}",
            p2(a),
            p2(b)
        ),
        format!(
            "in the top view the {what} lies within x {} to {} mm, y {} to {} mm: place the section across the addendum{ends}, the first `at` point inside the product outline and the second beyond the punch opening",
            num(lo.x),
            num(hi.x),
            num(lo.y),
            num(hi.y)
        ),
    )
}

/// The top-view bounding box of a curve, from samples.
fn top_bounds(c: &Curve3) -> (DVec2, DVec2) {
    let (t0, t1) = c.domain();
    let n = 512;
    (0..=n)
        .map(|i| c.point_at(t0 + (t1 - t0) * i as f64 / n as f64).truncate())
        .fold(
            (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY)),
            |(lo, hi), p| (lo.min(p), hi.max(p)),
        )
}

/// A length as a designer reads it: to the thousandth of a millimetre.
fn num(x: f64) -> String {
    show((x * 1000.0).round() / 1000.0)
}

/// A point `(s, z)` or `(x, y)`.
fn p2(p: DVec2) -> String {
    format!("({}, {})", num(p.x), num(p.y))
}

/// Below this angle (degrees) between a section plane and the product outline, the plane
/// runs along the outline rather than across it.
const GRAZING: f64 = 20.0;

/// The parts of a step-draw block a problem is blamed on, by key-section index.
enum Part {
    /// The section's name in `section NAME`.
    Name(usize),
    /// The section's `at` points.
    At(usize),
    /// The section's `profile`.
    Profile(usize),
    /// The first or last segment of the section's profile sketch, when it is written in
    /// this file.
    ProfileEnd { section: usize, first: bool },
    /// The segment of the section's profile sketch nearest a point (s, z), when it is
    /// written in this file.
    SegmentNear { section: usize, at: DVec2 },
}

/// What the kernel's problems are told with.
struct Context<'a, 'b> {
    block: &'a Block<'b>,
    guides: &'a Guides,
    sections: &'a [SectionSource],
    tolerance: f64,
}

impl Context<'_, '_> {
    /// The diagnostic of the kernel's problem `p` at key section `k`.
    fn diagnose(&self, k: usize, p: &Problem) -> Diagnostic {
        diagnostic(KIND, self.block, self.explain(k, p), |part| {
            self.resolve(part)
        })
    }

    /// Where the part of the block `part` was written.
    fn resolve(&self, part: &Part) -> Option<Span> {
        let file = self.block.span.file;
        let here = |s: Span| (s.file == file).then_some(s);
        match *part {
            Part::Name(k) => self.sections.get(k).map(|s| s.name_span),
            Part::At(k) => self.sections.get(k).map(|s| s.at),
            Part::Profile(k) => self.sections.get(k).map(|s| s.profile),
            Part::ProfileEnd { section, first } => {
                let segments = &self.sections.get(section)?.sketch.as_ref()?.segments;
                let seg = if first {
                    segments.first()?
                } else {
                    segments.last()?
                };
                here(seg.span)
            }
            Part::SegmentNear { section, at } => {
                let sketch = self.sections.get(section)?.sketch.as_ref()?;
                let (t0, t1) = sketch.curve.domain();
                let n = 2000;
                let t = (0..=n)
                    .map(|i| t0 + (t1 - t0) * i as f64 / n as f64)
                    .min_by(|x, y| {
                        let dx = sketch.curve.point_at(*x).distance(at);
                        let dy = sketch.curve.point_at(*y).distance(at);
                        dx.total_cmp(&dy)
                    })?;
                let seg = sketch
                    .segments
                    .iter()
                    .find(|s| s.range.0 <= t && t <= s.range.1)?;
                here(seg.span)
            }
        }
    }

    /// What the designer reads about the kernel's problem `p` at key section `k`.
    fn explain(&self, k: usize, p: &Problem) -> Explanation<Part> {
        let Some(src) = self.sections.get(k) else {
            return match p {
                Problem::TooFewSections { needed } => self.too_few(*needed),
                p => Explanation::new(
                    format!("the step draw `{}` cannot be built: {p}", self.block.name),
                    Blame::Block,
                    "this step draw",
                    "check the sections' `at` points and profiles",
                ),
            };
        };
        match p {
            Problem::TooFewSections { needed } => self.too_few(*needed),
            Problem::MissesGuide { product } => {
                misses_guide(self.guides, *product, &src.name, k, src.a, src.b)
            }
            Problem::EndsOffGuides {
                product, opening, ..
            } => self
                .grazing(k, src)
                .unwrap_or_else(|| self.ends_off(k, src, *product, *opening)),
            Problem::FoldsBack { at } => self
                .grazing(k, src)
                .unwrap_or_else(|| self.folds_back(k, src, *at)),
            Problem::WrongOrder => self.wrong_order(k),
            Problem::ProductNotCubic => not_cubic(&self.guides.product),
            Problem::CannotReach { at } => Explanation::new(
                format!(
                    "between section `{}` and the one before it, the section at ({:.2}, {:.2}, {:.2}) cannot reach the punch opening with the key sections' runs and corners",
                    src.name, at.x, at.y, at.z
                ),
                Part::Profile(k),
                "the profile carried here",
                "the opening comes too close to the product there for the walls and radii of the neighbouring key sections: add a key section there with a profile that fits, or move the opening out",
            ),
            Problem::Kernel(e) => self.grazing(k, src).unwrap_or_else(|| {
                Explanation::new(
                    format!("the step draw `{}` cannot be built at section `{}`: {e}", self.block.name, src.name),
                    Part::Name(k),
                    "cannot be built here",
                    "check this section's `at` points and profile, and its neighbours': sections very close together, or planes crossing inside the addendum, leave no room for a patch",
                )
                .also(Part::Profile(k), "this profile")
            }),
        }
    }

    fn too_few(&self, needed: usize) -> Explanation<Part> {
        let n = self.sections.len();
        let has = match n {
            0 => "none".to_string(),
            n => n.to_string(),
        };
        let (message, help) = if self.guides.closed {
            (
                format!("a closed step draw needs at least {needed} sections, but `{}` has {has}", self.block.name),
                "the outline is closed, so the sections go all the way round it: add `section NAME { at = ((x1, y1), (x2, y2)); profile = ... }` blocks in order around the outline (counter-clockwise seen from above), one where the profile changes and a few along each long side",
            )
        } else {
            (
                format!("an open step draw needs at least {needed} sections, but `{}` has {has}", self.block.name),
                "an open step draw runs from its first section to its last: add `section NAME { at = ((x1, y1), (x2, y2)); profile = ... }` blocks in order along the outline, one near each end of it and one where the profile changes",
            )
        };
        let label = match n {
            0 => "no sections".to_string(),
            1 => "1 section".to_string(),
            n => format!("{n} sections"),
        };
        Explanation::new(message, Blame::Block, label, help)
    }

    /// When the plane of section `k` runs along the product outline rather than across
    /// it, that is the problem to report.
    fn grazing(&self, k: usize, src: &SectionSource) -> Option<Explanation<Part>> {
        let tangent = self
            .guides
            .product
            .derivative_at(src.ends.product_t)
            .truncate()
            .normalize_or_zero();
        let d = (src.b - src.a).normalize_or_zero();
        if tangent == DVec2::ZERO || d == DVec2::ZERO {
            return None;
        }
        let angle = tangent.dot(d).abs().min(1.0).acos().to_degrees();
        (angle < GRAZING).then(|| {
            Explanation::new(
                format!("the plane of section `{}` runs along the product outline instead of across it", src.name),
                Part::At(k),
                format!("crosses the outline at {} deg", num(angle)),
                "place the two `at` points on a line across the addendum, roughly square to the outline: the first inside the product outline, the second beyond the punch opening",
            )
        })
    }

    fn ends_off(
        &self,
        k: usize,
        src: &SectionSource,
        product: DVec2,
        opening: DVec2,
    ) -> Explanation<Part> {
        let tol = self.tolerance;
        let (p0, p1) = (src.curve.start_point(), src.curve.end_point());
        // The kernel's pairing: the profile may run either way.
        let forward = p0.distance(product) + p1.distance(opening)
            <= p1.distance(product) + p0.distance(opening);
        let pairs = if forward {
            [
                (p0, true, product, "product outline"),
                (p1, false, opening, "punch opening"),
            ]
        } else {
            [
                (p1, false, product, "product outline"),
                (p0, true, opening, "punch opening"),
            ]
        };
        let off: Vec<_> = pairs
            .iter()
            .filter(|(p, _, q, _)| p.distance(*q) > tol)
            .collect();
        let says = |(p, first, q, what): &(DVec2, bool, DVec2, &str)| {
            format!(
                "{} at {}, {} mm from the {what} at {}",
                if *first { "starts" } else { "ends" },
                p2(*p),
                num(p.distance(*q)),
                p2(*q)
            )
        };
        let reach = match off.as_slice() {
            [one] => format!("the {}", one.3),
            _ => "the product outline and the punch opening".to_string(),
        };
        let message = format!(
            "the profile of section `{}` does not reach {reach}",
            src.name
        );
        let view_note = match src.sketch.as_ref().map(|s| s.view) {
            Some(View::Section { a, b })
                if a.distance(src.a) > 1e-6
                    || (b - a).normalize_or_zero().distance((src.b - src.a).normalize_or_zero()) > 1e-9 =>
            {
                format!(
                    "; the sketch is drawn in `section({}, {})`, but the section is `at = ({}, {})`",
                    p2(a),
                    p2(b),
                    p2(src.a),
                    p2(src.b)
                )
            }
            Some(v @ (View::SideXZ | View::SideYZ)) => format!(
                "; a `{}` sketch measures from the press origin, a section profile from the first `at` point: draw it in `section({}, {})` or `profile`",
                v.name(),
                p2(src.a),
                p2(src.b)
            ),
            _ => String::new(),
        };
        let help = format!(
            "in this section plane, s from {} towards {} and z up, the product outline is at {} and the punch opening at {}: start and end the profile there (within the tolerance, {} mm), or give a profile function, which is handed both points (`profile = add.wall`){view_note}",
            p2(src.a),
            p2(src.b),
            p2(product),
            p2(opening),
            num(tol),
        );
        let end = |x: &(DVec2, bool, DVec2, &str)| Part::ProfileEnd {
            section: k,
            first: x.1,
        };
        // Point at the profile's ends that miss, when it is drawn here; else at the profile.
        let Some((first, rest)) = off.split_first() else {
            return Explanation::new(message, Part::Profile(k), "this profile", help);
        };
        let all = off.iter().map(|x| says(x)).collect::<Vec<_>>().join("; ");
        let mut x = Explanation::new(message, end(first), says(first), help)
            .or_labelled(Part::Profile(k), format!("it {all}"));
        for r in rest {
            x = x.also(end(r), says(r));
        }
        x.also(
            Part::Profile(k),
            format!("the profile of section `{}`", src.name),
        )
    }

    fn folds_back(&self, k: usize, src: &SectionSource, at: DVec2) -> Explanation<Part> {
        let (product, opening) = (src.ends.product, src.ends.opening);
        if let Some(f) = &src.function {
            if opening.x < product.x {
                return Explanation::new(
                    format!("the `at` points of section `{}` run from the punch opening inwards, so its profile `{f}` folds back", src.name),
                    Part::At(k),
                    format!("from the outside in: the punch opening is at s {}, the product outline at s {}", num(opening.x), num(product.x)),
                    format!(
                        "s runs from the first `at` point towards the second, and profile functions draw outwards along s: swap the points, `at = ({}, {})`",
                        p2(src.b),
                        p2(src.a)
                    ),
                )
                .also(Part::Profile(k), format!("`{f}` draws from the product outwards"));
            }
        }
        let message = format!(
            "the profile of section `{}` folds back on itself near {}",
            src.name,
            p2(at)
        );
        // Where the profile is drawn here, the segment that runs back says it all.
        let near = Part::SegmentNear { section: k, at };
        if self.resolve(&near).is_some() {
            return Explanation::new(message, near, "runs back towards the product here", "a step-draw profile runs outwards from the product outline to the punch opening, every point at least as far out as the ones before it (a vertical wall is allowed, an undercut is not): move this point outwards, or draw the profile again")
                .also(Part::Profile(k), format!("the profile of section `{}`", src.name));
        }
        let Some(f) = &src.function else {
            return Explanation::new(
                message,
                Part::Profile(k),
                "this profile folds back",
                "a step-draw profile runs outwards from the product outline to the punch opening, every point at least as far out as the ones before it (a vertical wall is allowed, an undercut is not)",
            );
        };
        let across = (opening.x - product.x).abs();
        let dz = opening.y - product.y;
        let height = if dz.abs() < 1e-6 {
            "at the same height".to_string()
        } else {
            format!(
                "{} mm {}",
                num(dz.abs()),
                if dz < 0.0 { "lower" } else { "higher" }
            )
        };
        Explanation::new(
            format!("{message}: `{f}` does not fit between the product outline and the punch opening"),
            Part::Profile(k),
            format!("`{f}` folds back here"),
            format!(
                "here the punch opening is {} mm out from the product outline and {height}: the profile's runs, radii and walls (at their draft) must fit in those {} mm; shorten the runs, make the radii or the draft smaller, or move the section to where the opening is further out",
                num(across),
                num(across)
            ),
        )
    }

    fn wrong_order(&self, k: usize) -> Explanation<Part> {
        let n = self.sections.len();
        let prev_k = if k == 0 { n.saturating_sub(1) } else { k - 1 };
        let (Some(src), Some(prev)) = (self.sections.get(k), self.sections.get(prev_k)) else {
            return Explanation::new(
                "the sections are not in order along the outline",
                Blame::Block,
                "in this step draw",
                "list the sections in order along the outline",
            );
        };
        let product = &self.guides.product;
        let here = product.point_at(src.ends.product_t);
        let there = product.point_at(prev.ends.product_t);
        if here.distance(there) < 1e-3 {
            return Explanation::new(
                format!("sections `{}` and `{}` cut the product outline at the same place", prev.name, src.name),
                Part::Name(k),
                format!("at the same place as `{}`", prev.name),
                "two sections at one place leave nothing between them: remove one, or move its `at` points along the outline",
            )
            .also(Part::Name(prev_k), format!("`{}` is here", prev.name));
        }
        let ts: Vec<f64> = self.sections.iter().map(|s| s.ends.product_t).collect();
        let order = along(&ts, self.guides.closed);
        if order.iter().enumerate().any(|(i, &j)| i != j) {
            let names: Vec<&str> = order
                .iter()
                .map(|&i| self.sections[i].name.as_str())
                .collect();
            let (way, from) = if self.guides.closed {
                ("around the outline", "counter-clockwise seen from above")
            } else {
                ("along the outline", "from its start")
            };
            return Explanation::new(
                format!(
                    "section `{}` is listed after `{}`, but comes before it {way}",
                    src.name, prev.name
                ),
                Part::Name(k),
                "out of order",
                format!(
                    "list the sections in order {way}, {from}: {}",
                    names.join(", ")
                ),
            )
            .also(Part::Name(prev_k), format!("listed before `{}`", src.name));
        }
        // In order along the product outline, not along the opening: the planes cross.
        Explanation::new(
            format!("the planes of sections `{}` and `{}` cross between the product outline and the punch opening", prev.name, src.name),
            Part::At(k),
            format!("`{}` comes after `{}` along the product outline, before it along the punch opening", src.name, prev.name),
            "turn the `at` points so that neighbouring planes do not cross inside the addendum: each roughly square to the outline",
        )
        .also(Part::At(prev_k), format!("the plane of `{}`", prev.name))
    }
}

/// The order of the sections along the guide by their parameters `ts`: for a closed guide
/// counter-clockwise from the first section.
fn along(ts: &[f64], closed: bool) -> Vec<usize> {
    let mut order: Vec<usize> = (0..ts.len()).collect();
    order.sort_by(|&i, &j| ts[i].total_cmp(&ts[j]));
    if closed {
        if let Some(p) = order.iter().position(|&i| i == 0) {
            order.rotate_left(p);
        }
    }
    order
}

/// How far (deg) a step-draw wall may overhang before it counts as folded over: a
/// vertical wall drawn in a profile may be fitted a hair past vertical, but every
/// profile runs outwards (an undercut profile is refused), so a wall that overhangs by
/// more than this has folded between the key sections.
const FOLDED_DRAFT: f64 = 1.0;

/// The feature record: one surface per patch, one curve per key section, `quality`;
/// an error when a patch has folded over (its wall overhangs by more than
/// [`FOLDED_DRAFT`]), before anything downstream meshes the fold.
fn output(block: &Block, sd_result: sd::StepDraw) -> Result<Value, Diagnostic> {
    let span = block.span;
    let mut fields: Vec<(String, Value)> = sd_result
        .patches
        .iter()
        .map(|p| {
            (
                p.name.clone(),
                Value::new(Data::Surface(Arc::new(p.surface.clone())), span),
            )
        })
        .collect();
    for (name, curve) in &sd_result.key_sections {
        fields.push((
            format!("section {name}"),
            Value::new(Data::Curve3(Arc::new(curve.clone())), span),
        ));
    }
    let q = &sd_result.quality;
    let (worst, joins) = join_figures(
        q.joins.iter().map(|(a, b, j)| (a.as_str(), b.as_str(), j)),
        span,
    );
    let mut quality = vec![
        ("product_gap".to_string(), mm(q.product_gap, span)),
        (
            "opening_deviation".to_string(),
            mm(q.opening_deviation, span),
        ),
        ("section_fit".to_string(), mm(q.section_fit, span)),
        ("end_snap".to_string(), mm(q.end_snap, span)),
        ("knot_move".to_string(), mm(q.knot_move, span)),
    ];
    for (name, seam) in [("trim", &q.trim), ("opening", &q.opening_seam)] {
        if let Some(seam) = seam {
            quality.extend([
                (format!("{name}_gap"), mm(seam.gap, span)),
                (format!("{name}_gap_at"), Value::point3(seam.gap_at, span)),
                (format!("{name}_crease"), super::deg(seam.crease, span)),
                (
                    format!("{name}_crease_at"),
                    Value::point3(seam.crease_at, span),
                ),
            ]);
        }
    }
    quality.extend(worst);
    for (name, m) in &q.per_section {
        quality.push((
            format!("section {name}"),
            super::record_value(
                vec![
                    ("end_snap".to_string(), mm(m.end_snap, span)),
                    ("knot_move".to_string(), mm(m.knot_move, span)),
                ],
                span,
            ),
        ));
    }
    quality.extend(joins);
    let patches = sd_result.patches.iter();
    let figures = super::surface_figures(
        &mut quality,
        patches.map(|p| {
            (
                p.name.as_str(),
                &p.surface,
                p.sections.as_slice(),
                Some(p.drawn_radius),
            )
        }),
        span,
    );
    let folded = figures
        .iter()
        .filter(|(_, f)| f.draft < -FOLDED_DRAFT)
        .min_by(|a, b| a.1.draft.total_cmp(&b.1.draft));
    if let Some((name, f)) = folded {
        let p = f.draft_at;
        return Err(feature_error(
            KIND,
            format!(
                "the step draw folds over in patch `{name}`: its wall overhangs by {:.1} deg at ({:.2}, {:.2}, {:.2})",
                -f.draft, p.x, p.y, p.z
            ),
            span,
            "folds over",
            "between two key sections the sections turn back on themselves, which no die can be drawn with: a die or punch radius of almost nothing, or key sections far apart round a tight corner of the outline. Open the radii, or add a key section where it folds",
        ));
    }
    Ok(feature_value(KIND, span, fields, quality, sd_result))
}

/// The `step_draw` feature kind.
pub(super) static KIND: &dyn FeatureKind = &StepDrawKind;

struct StepDrawKind;

impl FeatureKind for StepDrawKind {
    fn name(&self) -> &'static str {
        "step_draw"
    }
    fn code(&self) -> &'static str {
        "die::step_draw"
    }
    fn fields(&self) -> FieldNames {
        FieldNames {
            single: vec![
                "product",
                "opening",
                "binder",
                "tolerance",
                "closed",
                "tangent_product",
                "tangent_binder",
            ],
            named: vec!["section"],
        }
    }
    fn build(&self, block: &Block) -> Result<Value, Diagnostic> {
        build(block)
    }
    fn color(&self) -> [f64; 3] {
        [0.95, 0.50, 0.10] // orange
    }
    fn summary(&self, record: &Record) -> String {
        let Some(s) = record.model::<sd::StepDraw>() else {
            return String::new();
        };
        let (area, extent) = patches_extent(s.patches.iter().map(|p| &p.surface));
        format!(
            "step draw, {} key sections [{}], {} patches, area {} mm², bounds {}",
            s.key_sections.len(),
            s.key_sections
                .iter()
                .map(|(n, _)| n.as_str())
                .collect::<Vec<_>>()
                .join(", "),
            s.patches.len(),
            area,
            extent
        )
    }
    /// The step draw's patches are faces of the die face.
    fn die_face(&self, name: &str, record: &Record, out: &mut DieFace) {
        if let Some(s) = record.model::<sd::StepDraw>() {
            out.faces.extend(s.patches.iter().map(|p| Face {
                name: format!("{name}/{}", p.name),
                shape: Shape::Patch(p.surface.clone()),
            }));
        }
    }
}
