//! The feature registry: one [`FeatureKind`] per kind of feature block.
//!
//! A feature kind is one module that implements [`FeatureKind`] (its keyword, its
//! fields, its build, its summary, its material colour, what it exports and which of
//! its pieces belong to the die face) plus one entry in [`Registry::standard`]. The
//! engine, `inspect`, the die model and the exporters ask the kind; none of them names
//! a feature.

use std::any::Any;
use std::fmt;
use std::sync::Arc;

use crate::diag::Diagnostic;
use crate::die::model::{DieFace, LineBead, PLAIN_COLOR};

use super::super::value::{Record, Value};
use super::Block;

/// One kind of feature block (`bead name { ... }`).
pub trait FeatureKind: Send + Sync {
    /// The declaration keyword: `bead`.
    fn name(&self) -> &'static str;

    /// The one-word fields (`product`, `tolerance`) and the words of the named fields
    /// (`side` in `side front = ...`) the block accepts; any other field is refused
    /// with "did you mean" before [`FeatureKind::build`] runs.
    fn fields(&self) -> FieldNames;

    /// Builds the feature from its evaluated block: a record of its pieces (what is
    /// exported and what scripts reach as `name.piece`) and `quality`, with the kernel
    /// model attached as a [`Built`] (see [`super::feature_value`]).
    fn build(&self, block: &Block) -> Result<Value, Diagnostic>;

    /// The diagnostic code of its input errors.
    fn code(&self) -> &'static str {
        "die::feature"
    }

    /// The base colour (linear RGB) of its material in the exported scene.
    fn color(&self) -> [f64; 3] {
        PLAIN_COLOR
    }

    /// Whether the record field `field` is exported as its own piece (a field that
    /// repeats others, such as the opening's closed `line`, is not).
    fn exports_field(&self, _field: &str) -> bool {
        true
    }

    /// One line for `inspect` and snapshots: its pieces and main figures.
    fn summary(&self, _record: &Record) -> String {
        String::new()
    }

    /// Its line bead for forming simulation, when it is a draw bead.
    fn line_bead(&self, _record: &Record) -> Option<LineBead> {
        None
    }

    /// The kind of the exported piece in record field `field`, when it is not the
    /// feature's own (a sheet's `solid` is a `solid`).
    fn piece_kind(&self, _field: &str) -> Option<&'static str> {
        None
    }

    /// Adds its faces to the die face (`name` is the declaration's name).
    fn die_face(&self, _name: &str, _record: &Record, _out: &mut DieFace) {}
}

/// The fields a feature block accepts.
#[derive(Debug, Clone)]
pub struct FieldNames {
    /// One-word fields.
    pub single: Vec<&'static str>,
    /// Words of `word <name>` fields.
    pub named: Vec<&'static str>,
}

/// A built feature: its kind and its kernel model, carried by the feature's record so
/// that later features build on it (a step draw on the opening and the binder) and
/// every consumer can ask the kind.
#[derive(Clone)]
pub struct Built {
    /// The kind that built it.
    pub kind: &'static dyn FeatureKind,
    model: Arc<dyn Any + Send + Sync>,
}

impl Built {
    /// Pairs a kind with the kernel model it built.
    pub fn new<T: Any + Send + Sync>(kind: &'static dyn FeatureKind, model: T) -> Built {
        Built {
            kind,
            model: Arc::new(model),
        }
    }

    /// The kernel model, when it is a `T` (a `PunchOpening`, a `Blankholder`, ...).
    pub fn model<T: Any>(&self) -> Option<&T> {
        self.model.downcast_ref()
    }

    /// The kernel model shared, when it is a `T`: for a feature that keeps it.
    pub fn shared<T: Any + Send + Sync>(&self) -> Option<Arc<T>> {
        self.model.clone().downcast().ok()
    }
}

impl fmt::Debug for Built {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "Built({})", self.kind.name())
    }
}

/// The feature kinds an engine knows.
#[derive(Clone)]
pub struct Registry {
    kinds: Vec<&'static dyn FeatureKind>,
}

impl Registry {
    /// The standard kinds: the die-face features, sheet parts, mesh rounds and
    /// `die_checks`.
    pub fn standard() -> Registry {
        Registry {
            kinds: vec![
                super::punch_opening::KIND,
                super::blankholder::KIND,
                super::step_draw::KIND,
                super::bead::KIND,
                super::sheet::KIND,
                super::round::KIND,
                super::round::REROUND,
                super::fill::KIND,
                super::die_checks::KIND,
            ],
        }
    }

    /// Adds a kind (replacing one of the same name).
    pub fn register(&mut self, kind: &'static dyn FeatureKind) {
        self.kinds.retain(|k| k.name() != kind.name());
        self.kinds.push(kind);
    }

    /// The kind named `name`.
    pub fn get(&self, name: &str) -> Option<&'static dyn FeatureKind> {
        self.kinds.iter().copied().find(|k| k.name() == name)
    }

    /// The keywords of every kind, in registration order.
    pub fn names(&self) -> impl Iterator<Item = &'static str> + '_ {
        self.kinds.iter().map(|k| k.name())
    }
}

impl Default for Registry {
    fn default() -> Self {
        Registry::standard()
    }
}
