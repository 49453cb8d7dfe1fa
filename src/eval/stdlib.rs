//! The standard library: `.die` modules written in the language itself, embedded in
//! the binary so scripts run from any directory. `import "std/NAME" as alias`.

/// `(name, source)` of every standard module.
const MODULES: &[(&str, &str)] = &[
    ("units", include_str!("../../stdlib/units.die")),
    ("sketch", include_str!("../../stdlib/sketch.die")),
    ("addendum", include_str!("../../stdlib/addendum.die")),
    ("beads", include_str!("../../stdlib/beads.die")),
];

/// The source of the standard module `name`.
pub fn get(name: &str) -> Option<&'static str> {
    MODULES.iter().find(|(n, _)| *n == name).map(|(_, s)| *s)
}

/// Names of the standard modules.
pub fn names() -> impl Iterator<Item = &'static str> {
    MODULES.iter().map(|(n, _)| *n)
}
