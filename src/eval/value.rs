//! Values of the language.
//!
//! Every [`Value`] remembers the span of the expression that made it. Numbers carry
//! their dimension (powers of length and angle) and are stored in base units (mm, rad),
//! so unit conversion happens once, at the literal. Kernel geometry is shared behind
//! `Arc`: values are immutable and cheap to copy.

use std::fmt;
use std::sync::Arc;

use glam::{DVec2, DVec3};

use crate::geom::mesh::Mesh;
use crate::geom::{Curve2, Curve3, NurbsSurface, Transform, TrimmedSurface};
use crate::syntax::ast::{Expr, Param};
use crate::syntax::{FileId, Span};

use super::builtins::Builtin;
use super::features::Built;
use super::sketch::{Sketch, View};

/// A number with its dimension, in base units (mm for length, rad for angle).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Quantity {
    /// Value in base units.
    pub value: f64,
    /// Dimension.
    pub dim: Dim,
    /// A number written without a unit (or computed only from such numbers): it takes
    /// the file's default unit where a length or an angle is needed.
    pub bare: bool,
}

impl Quantity {
    /// A dimensionless number written without a unit.
    pub fn bare(value: f64) -> Self {
        Self {
            value,
            dim: Dim::NONE,
            bare: true,
        }
    }
    /// A dimensionless number that is not bare (a ratio, a percentage).
    pub fn ratio(value: f64) -> Self {
        Self {
            value,
            dim: Dim::NONE,
            bare: false,
        }
    }
    /// A length in mm.
    pub fn length(mm: f64) -> Self {
        Self {
            value: mm,
            dim: Dim::LENGTH,
            bare: false,
        }
    }
    /// An angle in radians.
    pub fn angle(rad: f64) -> Self {
        Self {
            value: rad,
            dim: Dim::ANGLE,
            bare: false,
        }
    }
}

/// A dimension: the powers of length and angle.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Dim {
    /// Power of length.
    pub length: i8,
    /// Power of angle.
    pub angle: i8,
}

impl Dim {
    /// Dimensionless.
    pub const NONE: Dim = Dim {
        length: 0,
        angle: 0,
    };
    /// A length.
    pub const LENGTH: Dim = Dim {
        length: 1,
        angle: 0,
    };
    /// An angle.
    pub const ANGLE: Dim = Dim {
        length: 0,
        angle: 1,
    };

    /// Whether dimensionless.
    pub fn is_none(self) -> bool {
        self == Dim::NONE
    }
}

impl fmt::Display for Dim {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let power = |name: &str, p: i8| match p {
            0 => String::new(),
            1 => name.to_string(),
            2 => format!("{name}²"),
            3 => format!("{name}³"),
            p => format!("{name}^{p}"),
        };
        let parts: Vec<String> = [power("length", self.length), power("angle", self.angle)]
            .into_iter()
            .filter(|s| !s.is_empty())
            .collect();
        if parts.is_empty() {
            f.write_str("a plain number")
        } else {
            f.write_str(&parts.join("·"))
        }
    }
}

/// A value with the span of the expression that made it.
#[derive(Debug, Clone)]
pub struct Value {
    /// What it is.
    pub data: Data,
    /// Where it was made.
    pub span: Span,
}

impl Value {
    /// Pairs data with its span.
    pub fn new(data: Data, span: Span) -> Self {
        Self { data, span }
    }

    /// A 2-D point as a tuple of two lengths.
    pub fn point2(p: DVec2, span: Span) -> Self {
        let c = |v: f64| Value::new(Data::Number(Quantity::length(v)), span);
        Value::new(Data::Tuple(Arc::new(vec![c(p.x), c(p.y)])), span)
    }

    /// A 3-D point as a tuple of three lengths.
    pub fn point3(p: DVec3, span: Span) -> Self {
        let c = |v: f64| Value::new(Data::Number(Quantity::length(v)), span);
        Value::new(Data::Tuple(Arc::new(vec![c(p.x), c(p.y), c(p.z)])), span)
    }

    /// The type name used in diagnostics ("a length", "a list", "a surface").
    pub fn type_name(&self) -> String {
        self.data.type_name()
    }
}

/// The kinds of values.
#[derive(Debug, Clone)]
pub enum Data {
    /// A number with a dimension.
    Number(Quantity),
    /// `true` / `false`.
    Bool(bool),
    /// Text.
    Str(Arc<str>),
    /// `[a, b, c]`
    List(Arc<Vec<Value>>),
    /// `(a, b)`, `(x, y, z)`: points and vectors are tuples of lengths.
    Tuple(Arc<Vec<Value>>),
    /// `{ a: 1 }`, and the value of a block declaration (with its kind).
    Record(Arc<Record>),
    /// A user function or lambda.
    Function(Arc<Closure>),
    /// A function implemented in Rust.
    Builtin(&'static Builtin),
    /// An imported module's namespace.
    Module(Arc<Module>),
    /// A named view or section plane that sketches are drawn in.
    View(View),
    /// A 2-D sketch: an exact NURBS profile in a view.
    Sketch(Arc<Sketch>),
    /// A 2-D NURBS curve (from a literal with 2-D points).
    Curve2(Arc<Curve2>),
    /// A 3-D NURBS curve.
    Curve3(Arc<Curve3>),
    /// A NURBS surface.
    Surface(Arc<NurbsSurface>),
    /// A surface trimmed at a closed outline on it (`trim(panel, outline)`): the
    /// product as the die face carries it.
    Trimmed(Arc<TrimmedSurface>),
    /// A triangle/quad mesh (a product read from OBJ).
    Mesh(Arc<Mesh>),
    /// An affine transform (behind an `Arc`: its matrix would make every value, and
    /// so every list item, four times larger).
    Transform(Arc<Transform>),
}

impl Data {
    /// The type name used in diagnostics.
    pub fn type_name(&self) -> String {
        match self {
            Data::Number(q) if q.bare && q.dim.is_none() => "a number".into(),
            Data::Number(q) => match q.dim {
                Dim::LENGTH => "a length".into(),
                Dim::ANGLE => "an angle".into(),
                d if d.is_none() => "a ratio".into(),
                d => format!("a quantity of dimension {d}"),
            },
            Data::Bool(_) => "a boolean".into(),
            Data::Str(_) => "a string".into(),
            Data::List(_) => "a list".into(),
            Data::Tuple(t) => format!("a {}-tuple", t.len()),
            Data::Record(r) => match &r.kind {
                Some(k) => format!("a {k}"),
                None => "a record".into(),
            },
            Data::Function(_) | Data::Builtin(_) => "a function".into(),
            Data::Module(_) => "a module".into(),
            Data::View(_) => "a view".into(),
            Data::Sketch(_) => "a sketch".into(),
            Data::Curve2(_) => "a 2-D curve".into(),
            Data::Curve3(_) => "a 3-D curve".into(),
            Data::Surface(_) => "a surface".into(),
            Data::Trimmed(_) => "a trimmed surface".into(),
            Data::Mesh(_) => "a mesh".into(),
            Data::Transform(_) => "a transform".into(),
        }
    }
}

/// Named fields in order; a block declaration's record also has its kind.
#[derive(Debug, Clone, Default)]
pub struct Record {
    /// `punch_opening`, `product`, ... for declaration blocks; `None` for literals.
    pub kind: Option<String>,
    /// Fields in source order.
    pub fields: Vec<(String, Value)>,
    /// For a feature, its kind and the kernel model its fields were taken from: what
    /// later features build on, and what the die model and the exporters ask.
    pub feature: Option<Built>,
}

impl Record {
    /// The field named `name`.
    pub fn get(&self, name: &str) -> Option<&Value> {
        self.fields.iter().find(|(n, _)| n == name).map(|(_, v)| v)
    }

    /// The kernel model of a feature's record, when it is a `T`.
    pub fn model<T: std::any::Any>(&self) -> Option<&T> {
        self.feature.as_ref().and_then(|f| f.model::<T>())
    }
}

/// A user-defined function or lambda with the environment it closes over.
#[derive(Debug, Clone)]
pub struct Closure {
    /// Name for diagnostics (`<lambda>` for lambdas).
    pub name: String,
    /// Parameters.
    pub params: Vec<Param>,
    /// Body.
    pub body: Arc<Expr>,
    /// Local bindings captured at creation (lambda inside a function or comprehension).
    pub captured: Vec<(String, Value)>,
    /// The file whose declarations the body sees.
    pub file: FileId,
}

/// An imported module: its declarations and functions by name.
#[derive(Debug, Clone)]
pub struct Module {
    /// The import path as written.
    pub path: String,
    /// The module's file.
    pub file: FileId,
    /// Exported values (declarations and functions), sorted by name.
    pub members: Vec<(String, Value)>,
}

impl Module {
    /// The member named `name`.
    pub fn get(&self, name: &str) -> Option<&Value> {
        self.members.iter().find(|(n, _)| n == name).map(|(_, v)| v)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A list holds its items by value: a large variant stored inline would make every
    /// item of every list that large (a matrix made each item 152 bytes; now 56).
    #[test]
    fn a_value_stays_small() {
        assert!(
            std::mem::size_of::<Value>() <= 56,
            "{}",
            std::mem::size_of::<Value>()
        );
    }
}
