//! The die face of an evaluated script as faces to sew: what a STEP export writes.
//!
//! In source order: every `product` that is a trimmed surface (or a surface, or a list
//! of them), the step draws' and blankholders' patches, and apart from them the draw
//! beads' skins (a bead sits on the binder with its own free boundary, so it is not
//! sewn into the die face). Curves, sketches and loose helper surfaces (`let`) are not
//! part of the die face.

use crate::geom::sew::{Face, Shape};

use super::value::{Data, Feature, Value};
use super::Outcome;

/// The faces of a die face.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct DieFaceFaces {
    /// Product, step draw and binder faces: one shell.
    pub faces: Vec<Face>,
    /// Bead skins: a second shell, each bead on its own.
    pub beads: Vec<Face>,
}

/// Collects the die face of `outcome` (declarations without a value are skipped).
pub fn die_face(outcome: &Outcome) -> DieFaceFaces {
    let mut out = DieFaceFaces::default();
    for d in &outcome.decls {
        let Some(value) = &d.value else { continue };
        if d.kind == "product" {
            product_faces(&d.name, value, &mut out.faces);
            continue;
        }
        let Data::Record(r) = &value.data else {
            continue;
        };
        let name = |piece: &str| format!("{}/{piece}", d.name);
        match &r.feature {
            Some(Feature::StepDraw(sd)) => out.faces.extend(sd.patches.iter().map(|p| Face {
                name: name(&p.name),
                shape: Shape::Patch(p.surface.clone()),
            })),
            Some(Feature::Blankholder(bh)) => out.faces.extend(bh.patches.iter().map(|p| Face {
                name: name(&p.name),
                shape: Shape::Patch(p.surface.clone()),
            })),
            Some(Feature::Bead(b)) => out.beads.push(Face {
                name: d.name.clone(),
                shape: Shape::Patch(b.surface.clone()),
            }),
            _ => {}
        }
    }
    out
}

fn product_faces(name: &str, value: &Value, out: &mut Vec<Face>) {
    match &value.data {
        Data::Trimmed(t) => out.push(Face {
            name: name.to_string(),
            shape: Shape::Trimmed((**t).clone()),
        }),
        Data::Surface(s) => out.push(Face {
            name: name.to_string(),
            shape: Shape::Patch((**s).clone()),
        }),
        Data::List(items) => {
            for (i, item) in items.iter().enumerate() {
                product_faces(&format!("{name}/{i}"), item, out);
            }
        }
        _ => {}
    }
}
