//! Evaluating a script through the language in a test: the values of its declarations,
//! or a panic that shows the rendered diagnostics.

#![allow(dead_code)] // each test file uses its own subset

use dieface::eval::{Data, Engine, Outcome, Value};

/// Every declaration of an evaluation with its value, in source order; panics with the
/// rendered diagnostics if there are any.
pub fn clean_values(engine: &Engine, outcome: &Outcome) -> Vec<(String, Value)> {
    let rendered: Vec<String> = outcome
        .diagnostics
        .iter()
        .map(|d| engine.sources.render(d, false))
        .collect();
    assert!(rendered.is_empty(), "{}", rendered.join("\n"));
    outcome
        .decls
        .iter()
        .filter_map(|d| d.value.clone().map(|v| (d.name.clone(), v)))
        .collect()
}

/// Evaluates `text` as the file `file` (no project folder) and returns every
/// declaration's data, in source order; panics on any diagnostic.
pub fn evaluate_clean(file: &str, text: &str) -> Vec<(String, Data)> {
    let mut engine = Engine::new(None);
    let outcome = engine.evaluate(file, text, None);
    clean_values(&engine, &outcome)
        .into_iter()
        .map(|(name, value)| (name, value.data))
        .collect()
}

/// The diagnostics of evaluating `text` as the file `file` (no project folder).
pub fn diagnostics_of(file: &str, text: &str) -> Vec<dieface::diag::Diagnostic> {
    Engine::new(None).evaluate(file, text, None).diagnostics
}

/// The sheet part the script's first `sheet` block builds (the script must evaluate
/// cleanly).
pub fn sheet_part(text: &str) -> dieface::sheet::part::SheetPart {
    evaluate_clean("part.die", text)
        .into_iter()
        .find_map(|(_, data)| match data {
            Data::Record(r) => r.model::<dieface::sheet::part::SheetPart>().cloned(),
            _ => None,
        })
        .expect("a sheet part")
}

/// A script of one `sheet part` at 1 mm over a 100 x 60 mm plate, with `flanges` (the
/// block's further lines).
pub fn plate_script(flanges: &str) -> String {
    format!(
        "units mm deg\nsheet part {{\n    outline = sketch(top) {{ from (0, 0); line to (100, 0); \
         line to (100, 60); line to (0, 60); close }}\n    thickness = 1 mm\n    {flanges}\n}}"
    )
}

/// Each `(lines, expected)`: the [`plate_script`] with `lines` in its block is refused
/// with a message holding `expected`.
pub fn assert_plate_refused(cases: &[(&str, &str)]) {
    for &(lines, expected) in cases {
        let found = diagnostics_of("part.die", &plate_script(lines));
        assert!(
            found.iter().any(|d| d.message.contains(expected)),
            "{expected}: {found:#?}"
        );
    }
}
