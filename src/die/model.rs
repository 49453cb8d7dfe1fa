//! The die model: what a build made, as plain kernel data.
//!
//! Evaluation (`eval`) turns a script into language values; this is the other side of
//! that boundary. Every exported declaration becomes a [`Part`]: a named tree of pieces
//! (surfaces, trimmed surfaces, meshes, curves), with the declaration's kind, its
//! material colour, the source line each piece came from, the feature's quality figures
//! and its simulation data (a bead's line bead). The die face to machine (what STEP
//! writes) is collected beside it as faces to sew.
//!
//! The exporters (glTF, OBJ, STEP, the FE writers), `inspect --json`'s geometry and the
//! viewer read this model and nothing of the language, so data flows one way:
//! `eval` -> `die::model` -> `export`.

use std::sync::Arc;

use glam::DVec3;

use crate::geom::fingerprint::Fingerprint;
use crate::geom::mesh::Mesh;
use crate::geom::sew::Face;
use crate::geom::{Curve3, NurbsSurface, TrimmedSurface};

/// The base colour (linear RGB) of parts whose kind names none: `let`, `param`.
pub const PLAIN_COLOR: [f64; 3] = [0.80, 0.80, 0.80];

/// Everything a build made from one script.
#[derive(Debug, Clone, Default)]
pub struct DieModel {
    /// The script's name as diagnostics show it (relative to the project root).
    pub source_name: String,
    /// One part per exported declaration, in source order.
    pub parts: Vec<Part>,
    /// The die face to machine: product, step draw and binder faces (one shell), and
    /// the beads' skins apart.
    pub die_face: DieFace,
}

/// One exported declaration, or one of its pieces.
#[derive(Debug, Clone)]
pub struct Part {
    /// Full path name: `fender`, `bead_lines/0`, `binder/front`.
    pub name: String,
    /// The declaration's kind (`product`, `let`, `bead`, ...); pieces inherit it.
    pub kind: String,
    /// The kind's material colour (linear RGB).
    pub color: [f64; 3],
    /// 1-based source line of the declaration, or of the piece's expression when it
    /// lies inside the declaration.
    pub line: usize,
    /// The piece's own geometry (none for a group).
    pub shape: Option<Shape>,
    /// Its pieces: a list's elements, a record's or feature's fields.
    pub children: Vec<Part>,
    /// For a draw bead, its line bead for forming simulation.
    pub line_bead: Option<LineBead>,
    /// For a feature, its quality figures (`quality` in the language), flattened.
    pub figures: Vec<Figure>,
}

/// The geometry of one piece, in press coordinates (mm, Z up).
#[derive(Debug, Clone)]
pub enum Shape {
    /// A NURBS surface.
    Surface(Arc<NurbsSurface>),
    /// A surface cut at its outline (the product at the trim line).
    Trimmed(Arc<TrimmedSurface>),
    /// A triangle/quad mesh.
    Mesh(Arc<Mesh>),
    /// A curve (2-D curves and sketches placed in their view).
    Curve(Arc<Curve3>),
}

impl Shape {
    /// The content fingerprint of the exact geometry: equal for equal shapes however
    /// they were made (the scene cache's key, and `diff`'s test of "unchanged").
    pub fn fingerprint(&self) -> u64 {
        match self {
            Shape::Surface(s) => s.fingerprint(),
            Shape::Trimmed(t) => t.fingerprint(),
            Shape::Mesh(m) => m.fingerprint(),
            Shape::Curve(c) => c.fingerprint(),
        }
    }
}

/// A line bead: the bead's centre line on the binder as points every `spacing`, with
/// the restraining force a forming simulation applies along it (LS-DYNA
/// `*CONTACT_DRAWBEAD`-style).
#[derive(Debug, Clone, PartialEq)]
pub struct LineBead {
    /// Points in press coordinates (mm).
    pub points: Vec<DVec3>,
    /// Distance between the points along the line (mm).
    pub spacing: f64,
    /// Restraining force per unit length (N/mm), if the script gives one.
    pub force: Option<f64>,
    /// The bead's depth: its tallest point above the binder (mm). LS-DYNA's draw bead
    /// contact needs it (DBDTH) to tell how far the blank has moved into the bead.
    pub depth: f64,
}

/// One quality figure of a feature: `min_radius`, `patch_a.draft`, ...
#[derive(Debug, Clone, PartialEq)]
pub struct Figure {
    /// Its name; a per-piece figure is `piece.figure`.
    pub name: String,
    /// Its value.
    pub value: FigureValue,
}

/// The value of a quality figure, in base units.
#[derive(Debug, Clone, PartialEq)]
pub enum FigureValue {
    /// A length in mm.
    Length(f64),
    /// An angle in degrees.
    Angle(f64),
    /// A plain number or ratio.
    Number(f64),
    /// A place in press coordinates (mm).
    Point(DVec3),
    /// Yes or no (`undercut`).
    Flag(bool),
}

/// The die face as faces to sew: what STEP writes.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct DieFace {
    /// Product, step draw and binder faces: one shell.
    pub faces: Vec<Face>,
    /// Bead skins: a second shell, each bead on its own.
    pub beads: Vec<Face>,
}

impl Part {
    /// This part and all its pieces, depth first, parents before children.
    pub fn walk(&self) -> Vec<&Part> {
        let mut out = vec![self];
        for c in &self.children {
            out.extend(c.walk());
        }
        out
    }
}

impl DieModel {
    /// Every part, depth first in source order, parents before children.
    pub fn all_parts(&self) -> Vec<&Part> {
        self.parts.iter().flat_map(Part::walk).collect()
    }
}
