//! A new feature kind is one module and one registration: a trivial `flange` (a
//! vertical wall hanging from a 3-D edge), defined here in the test, registered with an
//! engine, is built from a script's block, checked for its fields, summarised by its
//! kind, and exported as a piece with its kind's colour, without touching the engine,
//! the die model or the exporters.

use std::sync::Arc;

use dieface::diag::Diagnostic;
use dieface::eval::features::explain::diagnostic;
use dieface::eval::features::{feature_value, Blame, Block, Explanation, FeatureKind, FieldNames};
use dieface::eval::summary::summarize;
use dieface::eval::value::{Data, Quantity, Record, Value};
use dieface::eval::Engine;
use dieface::export::scene::build_scene;
use dieface::geom::construct::ruled;
use dieface::geom::tessellate::Tolerance;
use dieface::geom::NurbsSurface;
use glam::DVec3;

#[path = "common/script.rs"]
mod script;

/// The kernel model of a flange: its wall.
struct Flange {
    wall: NurbsSurface,
}

struct FlangeKind;

static FLANGE: FlangeKind = FlangeKind;

const COLOUR: [f64; 3] = [0.1, 0.2, 0.9];

impl FeatureKind for FlangeKind {
    fn name(&self) -> &'static str {
        "flange"
    }
    fn fields(&self) -> FieldNames {
        FieldNames {
            single: vec!["edge", "height"],
            named: Vec::new(),
        }
    }
    fn build(&self, block: &Block) -> Result<Value, Diagnostic> {
        let edge = match block.get("edge").map(|f| &f.value.data) {
            Some(Data::Curve3(c)) => (**c).clone(),
            _ => return Err(block.missing("edge", "give the flange's edge as a 3-D curve")),
        };
        let height = block.length_or("height", 10.0)?;
        if height > edge.length() {
            // A problem told as data: the inputs it blames, resolved by the shared
            // `diagnostic` (a flange has no parts of its own to resolve).
            let explanation = Explanation::<()>::new(
                format!(
                    "the flange `{}` hangs lower than its edge is long",
                    block.name
                ),
                Blame::Field("height"),
                "this height",
                "give a height shorter than the edge",
            )
            .also(Blame::Field("edge"), "this edge")
            .also(Blame::Block, "this flange");
            return Err(diagnostic(self, block, explanation, |_| None));
        }
        let foot = edge.map_points(|p| p - DVec3::Z * height);
        let wall = ruled(&edge, &foot).expect("two compatible curves");
        let fields = vec![(
            "wall".to_string(),
            Value::new(Data::Surface(Arc::new(wall.clone())), block.span),
        )];
        let quality = vec![(
            "height".to_string(),
            Value::new(Data::Number(Quantity::length(height)), block.span),
        )];
        Ok(feature_value(
            &FLANGE,
            block.span,
            fields,
            quality,
            Flange { wall },
        ))
    }
    fn color(&self) -> [f64; 3] {
        COLOUR
    }
    fn summary(&self, record: &Record) -> String {
        let flange = record.model::<Flange>().expect("a flange's record");
        format!("flange, area {:.0} mm²", flange.wall.area())
    }
}

const SCRIPT: &str = "
let edge = interpolate([(0, 0, 0), (25, 0, 0), (50, 0, 0), (75, 0, 0), (100, 0, 0)])
flange lip {
    edge = edge
    height = 20 mm
}
";

#[test]
fn a_registered_kind_is_built_summarised_and_exported() {
    let mut engine = Engine::new(None);
    engine.register(&FLANGE);
    let outcome = engine.evaluate("lip.die", SCRIPT, None);
    let values = script::clean_values(&engine, &outcome);
    let (_, lip) = values
        .iter()
        .find(|(n, _)| n == "lip")
        .expect("the flange has a value");
    assert_eq!(summarize(lip), "flange, area 2000 mm²");

    let model = engine.die_model(&outcome);
    let part = model
        .parts
        .iter()
        .find(|p| p.name == "lip")
        .expect("the flange is a part");
    assert_eq!(part.kind, "flange");
    assert_eq!(part.color, COLOUR);
    assert_eq!(part.children.len(), 1, "its wall, not its quality record");
    assert_eq!(part.children[0].name, "lip/wall");
    assert!(part.figures.iter().any(|f| f.name == "height"));

    let scene = build_scene(&model, &Tolerance::new(0.05).unwrap()).expect("tessellates");
    let wall = scene.find("lip/wall").expect("the wall is a node");
    assert_eq!(wall.kind, "flange");
    assert!(!wall.geometry.is_empty());
}

#[test]
fn an_unregistered_kind_is_refused_and_a_registered_one_checks_its_fields() {
    let mut plain = Engine::new(None);
    let outcome = plain.evaluate("lip.die", SCRIPT, None);
    assert_eq!(outcome.diagnostics.len(), 1);
    assert_eq!(outcome.diagnostics[0].code, "die::unknown_kind");

    let mut engine = Engine::new(None);
    engine.register(&FLANGE);
    let outcome = engine.evaluate("lip.die", &SCRIPT.replace("height", "hieght"), None);
    assert_eq!(outcome.diagnostics.len(), 1);
    let d = &outcome.diagnostics[0];
    assert_eq!(d.code, "die::unknown_field");
    assert!(
        d.help
            .as_deref()
            .unwrap_or("")
            .contains("did you mean `height`"),
        "{:?}",
        d.help
    );
}

#[test]
fn a_kinds_problem_told_as_data_points_at_the_inputs_it_blames() {
    let mut engine = Engine::new(None);
    engine.register(&FLANGE);
    let mut places = |script: &str| {
        let outcome = engine.evaluate("lip.die", script, None);
        assert_eq!(outcome.diagnostics.len(), 1, "{:?}", outcome.diagnostics);
        let d = &outcome.diagnostics[0];
        assert_eq!(d.code, "die::feature", "the kind's code");
        assert_eq!(
            d.help.as_deref(),
            Some("give a height shorter than the edge")
        );
        let mut places = vec![(
            engine.sources.slice(d.primary.span).to_string(),
            d.primary.message.clone(),
        )];
        places.extend(
            d.secondary
                .iter()
                .map(|l| (engine.sources.slice(l.span).to_string(), l.message.clone())),
        );
        places
    };
    let text = |pairs: &[(&str, &str)]| -> Vec<(String, String)> {
        pairs
            .iter()
            .map(|(a, b)| (a.to_string(), b.to_string()))
            .collect()
    };
    // The blamed height was written: the primary label is at it.
    assert_eq!(
        places(&SCRIPT.replace("20 mm", "200 mm")),
        text(&[
            ("200 mm", "this height"),
            ("edge", "this edge"),
            ("flange", "this flange")
        ])
    );
    // No height written (the default is too long): the primary label falls back to the
    // block's head, and the head's own label is not repeated.
    let short = "
let edge = interpolate([(0, 0, 0), (1, 0, 0), (2, 0, 0), (3, 0, 0), (4, 0, 0)])
flange lip {
    edge = edge
}
";
    assert_eq!(
        places(short),
        text(&[("flange", "this height"), ("edge", "this edge")])
    );
}
