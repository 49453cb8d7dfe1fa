//! `die_checks` on the fender: limits set just inside the figures the features report
//! pass, with the margins in the value; a limit just outside fails at the feature's
//! name in `features`, naming the patch. The limits are taken from the fender's own
//! figures, so the test holds whatever the geometry's figures are.

use dieface::eval::{Data, Engine, Outcome, Value};

fn fender_text() -> String {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/examples/fender/fender.die");
    std::fs::read_to_string(path).expect("the fender example is readable")
}

fn evaluate(text: &str) -> (Engine, Outcome) {
    let mut engine = Engine::new(None);
    let outcome = engine.evaluate("fender.die", text, None);
    (engine, outcome)
}

fn decl<'o>(outcome: &'o Outcome, name: &str) -> &'o Value {
    outcome
        .decls
        .iter()
        .find(|d| d.name == name)
        .and_then(|d| d.value.as_ref())
        .unwrap_or_else(|| panic!("`{name}` has a value"))
}

fn field<'v>(v: &'v Value, name: &str) -> &'v Value {
    match &v.data {
        Data::Record(r) => r.get(name).unwrap_or_else(|| panic!("a field `{name}`")),
        _ => panic!("a record"),
    }
}

/// A length in mm or an angle in degrees.
fn number(v: &Value) -> f64 {
    match &v.data {
        Data::Number(q) if q.dim == dieface::eval::value::Dim::ANGLE => q.value.to_degrees(),
        Data::Number(q) => q.value,
        _ => panic!("a number"),
    }
}

/// The step draw's smallest radius and draft, read through the language
/// (`addendum.quality.min_radius`, bound to `checked_radius` by the script).
fn addendum_figures(outcome: &Outcome) -> (f64, f64) {
    (
        number(decl(outcome, "checked_radius")),
        number(decl(outcome, "checked_draft")),
    )
}

#[test]
fn limits_inside_the_fender_figures_pass_and_record_their_margins() {
    let text = fender_text()
        + "\nlet checked_radius = addendum.quality.min_radius\n\
           let checked_draft = addendum.quality.draft\n";
    let (engine, outcome) = evaluate(&text);
    assert!(
        outcome.diagnostics.is_empty(),
        "{}",
        outcome
            .diagnostics
            .iter()
            .map(|d| engine.sources.render(d, false))
            .collect::<String>()
    );
    let (radius, draft) = addendum_figures(&outcome);
    assert!(radius > 0.0 && radius.is_finite() && draft > 0.0 && draft < 90.0);
    let binder_radius = number(field(
        field(decl(&outcome, "binder"), "quality"),
        "min_radius",
    ));

    let limit_radius = 0.9 * radius.min(binder_radius);
    let limit_draft = draft - 0.5;
    let checks = format!(
        "die_checks limits {{\n    features = [addendum, binder]\n    \
         min_radius = {limit_radius} mm\n    min_draft = {limit_draft} deg\n}}\n"
    );
    let (engine, outcome) = evaluate(&(text + &checks));
    assert!(
        outcome.diagnostics.is_empty(),
        "{}",
        outcome
            .diagnostics
            .iter()
            .map(|d| engine.sources.render(d, false))
            .collect::<String>()
    );
    let limits = decl(&outcome, "limits");
    let r = field(field(limits, "addendum"), "min_radius");
    assert!((number(field(r, "worst")) - radius).abs() < 1e-9);
    assert!((number(field(r, "limit")) - limit_radius).abs() < 1e-9);
    assert!((number(field(r, "margin")) - (radius - limit_radius)).abs() < 1e-9);
    let d = field(field(limits, "addendum"), "min_draft");
    assert!((number(field(d, "margin")) - 0.5).abs() < 1e-9);
    let b = field(field(limits, "binder"), "min_radius");
    assert!((number(field(b, "worst")) - binder_radius).abs() < 1e-9);
}

#[test]
fn a_limit_just_outside_the_figure_fails_at_the_feature_naming_the_patch() {
    let probe = fender_text()
        + "\nlet checked_radius = addendum.quality.min_radius\n\
           let checked_draft = addendum.quality.draft\n";
    let (_, outcome) = evaluate(&probe);
    let (radius, _) = addendum_figures(&outcome);
    // The patch whose own record holds the worst radius.
    let quality = field(decl(&outcome, "addendum"), "quality");
    let Data::Record(q) = &quality.data else {
        panic!("a record")
    };
    let patch = q
        .fields
        .iter()
        .find(|(_, v)| match &v.data {
            Data::Record(r) => r.get("min_radius").map(number) == Some(radius),
            _ => false,
        })
        .map(|(n, _)| n.clone())
        .expect("a patch holds the worst radius");

    // The punch opening has no radius figure: it is skipped, not an error.
    let checks = format!(
        "die_checks limits {{\n    features = [opening, addendum]\n    min_radius = {} mm\n}}\n",
        radius + 0.01
    );
    let text = probe + &checks;
    let (engine, outcome) = evaluate(&text);
    let errors: Vec<_> = outcome
        .diagnostics
        .iter()
        .filter(|d| d.code == "die::die_checks")
        .collect();
    assert_eq!(errors.len(), 1, "one diagnostic for the block");
    let d = errors[0];
    assert_eq!(engine.sources.slice(d.primary.span), "addendum");
    assert!(
        d.message.contains(&format!("patch `{patch}`")),
        "{}",
        d.message
    );
    assert!(d.message.contains("min_radius"), "{}", d.message);
    assert_eq!(engine.sources.slice(d.secondary[0].span), "min_radius");
}
