//! The bracket's, the tray's and the hood reinforcement's solids against the same
//! parts thickened by OpenCascade (issue 15), from the committed reference data
//! (`tests/data/sheet_reference.json`, written by `tests/reference/sheet_reference.py`,
//! which builds each part from its example's numbers with exact arcs and surfaces and
//! thickens it with `BRepOffset_MakeOffset`).

#[path = "common/example.rs"]
mod example;

#[path = "common/script.rs"]
mod script;

use std::path::Path;

use dieface::eval::Data;
use dieface::sheet::part::SheetPart;
use serde_json::Value as Json;

fn reference() -> Json {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/sheet_reference.json");
    serde_json::from_str(&std::fs::read_to_string(path).expect("the reference data")).expect("JSON")
}

fn number(j: &Json) -> f64 {
    j.as_f64().expect("a number")
}

/// dieface's part differs from OpenCascade's only where dieface follows an arc by
/// chords (an outline's arcs, a bend's cylinder): in area by less than the tolerance
/// times the arcs' length, in volume by that times the gauge, and no point of either
/// solid lies further than the tolerance from the other. The data is current: it holds
/// the volume dieface makes now.
fn matches_opencascade(name: &str) {
    let values = example::example_values(&format!("{name}/{name}.die"));
    let (_, value) = values.iter().find(|(n, _)| n == name).expect("the part");
    let Data::Record(record) = &value.data else {
        panic!("a record")
    };
    let part = record.model::<SheetPart>().expect("a sheet part");
    part_matches_opencascade(name, part);
}

/// [`matches_opencascade`] for the part `part` the reference data holds as `name`.
fn part_matches_opencascade(name: &str, part: &SheetPart) {
    let r = reference();
    let tolerance = number(&r["tolerance"]);
    let r = &r["parts"][name];
    let gauge = number(&r["gauge"]);
    let occ = &r["occ"];
    assert_eq!(
        occ["valid"],
        Json::Bool(true),
        "OpenCascade's solid is invalid"
    );
    let (occ_area, occ_volume) = (number(&occ["mid_area"]), number(&occ["volume"]));
    // Chords of arcs within the tolerance. On a mid-surface of straight edges only,
    // OpenCascade thickens dieface's own sheets as the OBJ gives them, each coordinate
    // within 5e-7 mm, so the two agree within the area times 1e-6.
    let chords = (tolerance * number(&occ["curved_length"])).max(1e-6 * occ_area);
    assert!(
        (part.area - occ_area).abs() < chords,
        "area {} against OpenCascade's {occ_area}",
        part.area
    );
    assert!(
        (part.volume - occ_volume).abs() < chords * gauge,
        "volume {} against OpenCascade's {occ_volume}",
        part.volume
    );
    // The recorded distances were measured on this solid (its OBJ, to 1e-6 mm).
    let recorded = number(&r["dieface"]["volume"]);
    assert!(
        (part.volume - recorded).abs() < 1e-6 * recorded,
        "the reference data is stale: dieface now makes {} mm³, the data has {recorded}; \
         rerun tests/reference/sheet_reference.py",
        part.volume
    );
    assert_eq!(
        r["dieface"]["triangles"].as_u64(),
        Some(part.solid.face_count() as u64),
        "the reference data is stale: rerun tests/reference/sheet_reference.py"
    );
    let d = &r["distance"];
    // Every vertex of dieface's solid lies on OpenCascade's: exactly where the sheets
    // are flat, within the bend's chord sag where OpenCascade has a cylinder.
    assert!(
        number(&d["dieface_to_occ"]) < number(&r["sag"]) + 1e-5,
        "{d}"
    );
    assert!(number(&d["occ_to_dieface"]) <= tolerance, "{d}");
}

/// The bracket: a plate with a bolt hole and a slot, a square flange, and a foot bent
/// down on a 2 mm radius (OpenCascade's bend an exact quarter cylinder).
#[test]
fn the_bracket_matches_opencascade_within_the_outline_tolerance() {
    matches_opencascade("bracket");
}

/// The tray: a floor with round corners in plan, a drain hole and a lifted pad, and a
/// drafted wall all round, its strips joined at closed corners where three sheets
/// meet (OpenCascade's wall exact cones round the corners).
#[test]
fn the_tray_matches_opencascade_within_the_outline_tolerance() {
    matches_opencascade("tray");
}

/// The hood reinforcement, laid on the hood's doubly curved skin (OpenCascade's plate the
/// same B-spline trimmed, its rib's top the skin's exact offset), compared without its
/// rear flange: OpenCascade's offset fails inside that curved fold. The flange is
/// checked on its own: each of dieface's vertices on its sides lies on OpenCascade's
/// exact offsets of the flange's ruled surface, and the whole part's mid-surface area
/// is OpenCascade's within the chords of the outline's arcs.
/// The example `name`'s script, and the script without the lines that start with any
/// of `dropped` (after indentation), which must be `count` lines.
fn example_without(name: &str, dropped: &[&str], count: usize) -> (String, String) {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join(format!("examples/{name}/{name}.die"));
    let text = std::fs::read_to_string(path).expect("the example");
    let kept: String = text
        .lines()
        .filter(|l| !dropped.iter().any(|d| l.trim_start().starts_with(d)))
        .map(|l| format!("{l}\n"))
        .collect();
    assert_eq!(kept.lines().count() + count, text.lines().count());
    (text, kept)
}

/// The reinforcement without its 2 mm tab, its rib and its rounded corners (what
/// OpenCascade's thickening takes: one gauge, and no drafted walls round the rib's
/// ends), thickened by OpenCascade from dieface's own mid-surface: the thickening alone
/// compared, bends on radii, the 60 deg flange and its lip, the holes.
#[test]
fn the_reinforcement_thickens_as_opencascade_thickens_its_sheets() {
    let (_, trimmed) = example_without(
        "reinforcement",
        &["flange tab", "lift rib", "fillet corner"],
        4,
    );
    part_matches_opencascade("reinforcement", &script::sheet_part(&trimmed));
}

/// The pan: drafted walls closed at the corners and a level brim joined all round,
/// four sheets at each rim corner. OpenCascade thickens its sheets (dieface's
/// mid-surface) with its own intersection joins, so where the four offset sides meet
/// at each rim corner is checked against an independent kernel.
#[test]
fn the_pan_matches_opencascade_at_its_four_sheet_corners() {
    matches_opencascade("pan");
}

#[test]
fn the_hood_reinforcement_matches_opencascade_on_its_curved_skin() {
    let (text, flangeless) = example_without("hood_reinforcement", &["flange rear"], 1);
    let part = script::sheet_part(&flangeless);
    part_matches_opencascade("hood_reinforcement", &part);
    // The whole part.
    let whole = script::sheet_part(&text);
    let r = &reference()["hood_flange"];
    let occ_area = number(&r["occ_mid_area"]);
    let recorded = number(&r["dieface_mid_area"]);
    assert!(
        (whole.area - recorded).abs() < 1e-6 * recorded,
        "the reference data is stale: dieface's mid-surface is now {} mm², the data has \
         {recorded}; rerun tests/reference/sheet_reference.py",
        whole.area
    );
    // The outline's arcs are followed by chords within the outline tolerance: the
    // rounded corners' and holes' arcs, 4 x 12 pi / 2 + 2 x 8.5 pi + 9 pi mm long.
    let arcs = 4.0 * 12.0 * std::f64::consts::FRAC_PI_2
        + 2.0 * 8.5 * std::f64::consts::PI
        + 9.0 * std::f64::consts::PI;
    let tolerance = number(&reference()["tolerance"]);
    assert!(
        (whole.area - occ_area).abs() < tolerance * arcs,
        "mid-surface {} against OpenCascade's {occ_area}",
        whole.area
    );
    // Half the gauge off the flange each way, to the laid tolerance at the mitre.
    assert!(
        number(&r["flange_sides_to_occ_offsets"]) < dieface::sheet::laid::LAID_TOLERANCE,
        "{r}"
    );
    assert!(r["flange_vertices"].as_u64().unwrap_or(0) > 100, "{r}");
}
