//! Covers (issue 15: "add a sheet on a working plane given by picked edges", paper 003,
//! Fig. 6(c): a new sheet on two picked edges of two sheets, added by Smep then Smel):
//! a `cover` across the far edges of two flanges closes a channel into a box section,
//! a passage made. Checked on sections whose solids are known in closed form, on the
//! sheet model's topology, and on the refusals.

#[path = "common/script.rs"]
mod script;

#[path = "common/sheet.rs"]
mod common;

use common::assert_sound;
use dieface::sheet::part::SheetPart;
use glam::DVec3;

const T: f64 = 1.0;

/// The mean normal of the solid's face group `name` (area-weighted, unit).
fn group_normal(part: &SheetPart, name: &str) -> DVec3 {
    let solid = &part.solid;
    let p = solid.positions();
    let g = solid
        .group(name)
        .unwrap_or_else(|| panic!("no group {name}"));
    g.faces()
        .iter()
        .map(|t| {
            let i = solid.faces()[t.0 as usize].indices();
            let (a, b, c) = (p[i[0] as usize], p[i[1] as usize], p[i[2] as usize]);
            (b - a).cross(c - a)
        })
        .sum::<DVec3>()
        .normalize()
}

/// A 100 x 60 plate with square walls 20 mm high on its two short edges, closed by a
/// cover across their far edges: a rectangular tube 60 mm long. Its section is the
/// ring between the mid-line rectangle 100 x 20 offset out and in by t/2, whose areas
/// differ by the perimeter times t, so the solid is A t exactly. The cover makes a
/// passage: the model's genus goes from 0 to 1, and its topology stays valid. The
/// cover's inside continues the plate's top (inside the tube, facing down).
#[test]
fn a_cover_closes_a_channel_into_a_tube() {
    let part = script::sheet_part(&script::plate_script(
        "flange right = { at: (100, 30), height: 20 mm }\n    flange left = { at: (0, 30), height: 20 mm }\n    cover lid = { on: [\"right\", \"left\"] }",
    ));
    assert_sound(&part.solid);
    let counts = part.sheet.check().expect("a valid sheet model");
    assert_eq!(counts.genus, 1, "a passage made");
    let area = 6000.0 + 2.0 * 60.0 * 20.0 + 6000.0;
    assert!((part.area - area).abs() < 1e-9 * area, "{}", part.area);
    let exact = ((100.0 + T) * (20.0 + T) - (100.0 - T) * (20.0 - T)) * 60.0;
    assert!((exact - area * T).abs() < 1e-9);
    assert!(
        (part.volume - exact).abs() < 1e-9 * exact,
        "{} against {exact}",
        part.volume
    );
    let down = group_normal(&part, "lid.inside");
    assert!(down.distance(DVec3::NEG_Z) < 1e-9, "{down}");
    assert!(group_normal(&part, "lid.outside").distance(DVec3::Z) < 1e-9);
    assert!(part.solid.group("lid.edge_1").is_some());
    assert!(part
        .sheets
        .iter()
        .any(|s| s.name == "lid" && (s.area - 6000.0).abs() < 1e-9));
    // Every junction is a plain square corner where a wall's end meets the plate's
    // edge or the cover's: type 1.
    assert_eq!(part.junctions.len(), 8);
    assert!(part.junctions.iter().all(|j| j.kind.number() == 1));
}

/// A section of four unlike sides: the right wall square and 20 mm high, the left
/// flange leaning out at 60 deg, 20 mm long, and the cover slanting between their far
/// edges. A polygon's offsets out and in by t/2 (mitred) differ in area by its
/// perimeter times t whatever its angles, so the solid is still A t exactly.
#[test]
fn a_slanted_cover_across_unlike_flanges_is_still_a_t() {
    let part = script::sheet_part(&script::plate_script(
        "flange right = { at: (100, 30), height: 20 mm }\n    flange left = { at: (0, 30), height: 20 mm, angle: 60 deg }\n    cover lid = { on: [\"left\", \"right\"] }",
    ));
    assert_sound(&part.solid);
    let lean = DVec3::new(-10.0, 0.0, 20.0 * 60f64.to_radians().sin());
    let lid = DVec3::new(100.0, 0.0, 20.0).distance(lean);
    let perimeter = 100.0 + 20.0 + 20.0 + lid;
    let exact = perimeter * 60.0 * T;
    assert!(
        (part.area * T - exact).abs() < 1e-9 * exact,
        "{}",
        part.area
    );
    assert!(
        (part.volume - exact).abs() < 1e-9 * exact,
        "{} against {exact}",
        part.volume
    );
}

/// A cover of its own gauge (1.5 mm on a 1 mm channel) is offset by half its own
/// thickness each way: the tube's section is then the rectangle from x = -0.5 to 100.5
/// and z = -0.5 to 20.75 less the one from 0.5 to 99.5 and 0.5 to 19.25, each
/// sheet's area times its own thickness.
#[test]
fn a_cover_of_its_own_gauge_is_offset_by_its_own_half() {
    let part = script::sheet_part(&script::plate_script(
        "flange right = { at: (100, 30), height: 20 mm }\n    flange left = { at: (0, 30), height: 20 mm }\n    cover lid = { on: [\"right\", \"left\"], thickness: 1.5 mm }",
    ));
    assert_sound(&part.solid);
    let exact: f64 = (101.0 * 21.25 - 99.0 * 18.75) * 60.0;
    assert!((exact - (6000.0 + 2400.0 + 6000.0 * 1.5)).abs() < 1e-9);
    assert!(
        (part.volume - exact).abs() < 1e-9 * exact,
        "{} against {exact}",
        part.volume
    );
    let lid = part.sheets.iter().find(|s| s.name == "lid").expect("lid");
    assert_eq!(lid.thickness, 1.5);
}

/// The script of the tube of [`a_cover_closes_a_channel_into_a_tube`] with `lines`
/// added to its block.
fn tube(lines: &str) -> String {
    script::plate_script(&format!(
        "flange right = {{ at: (100, 30), height: 20 mm }}\n    flange left = {{ at: (0, 30), height: 20 mm }}\n    cover lid = {{ on: [\"right\", \"left\"] }}\n    {lines}"
    ))
}

/// The paper's third case of removal (section 4.4, Fig. 11(c)): a face whose rim runs
/// free in two runs, so taking it away loses a passage. The tube's lid taken off leaves
/// the channel (A t: 8,400 mm³); a wall taken off instead leaves the plate, the other
/// wall and the lid, a C section (13,200 mm³). Either way the genus falls back to 0,
/// and `quality.removals` says so. A wall taken off and then the lid (which then stands
/// on one wall only, free on three sides) trims the sheet and changes no passage.
#[test]
fn taking_a_tube_apart_loses_its_passage() {
    for (lines, area, cases) in [
        (
            "remove off = { cover: \"lid\" }",
            8400.0,
            &["trimmed, 1 passage(s) closed"][..],
        ),
        (
            "remove gone = { flange: \"left\" }",
            13200.0,
            &["trimmed, 1 passage(s) closed"][..],
        ),
        (
            "remove gone = { flange: \"left\" }\n    remove off = { cover: \"lid\" }",
            7200.0,
            &[
                "trimmed, 1 passage(s) closed",
                "trimmed, no passage changed",
            ][..],
        ),
    ] {
        let part = script::sheet_part(&tube(lines));
        assert_sound(&part.solid);
        assert_eq!(part.sheet.check().expect("valid").genus, 0, "{lines}");
        assert!(
            (part.area - area).abs() < 1e-9 * area,
            "{lines}: {}",
            part.area
        );
        assert!(
            (part.volume - area * T).abs() < 1e-9 * area,
            "{lines}: {}",
            part.volume
        );
        assert_eq!(part.removals.len(), cases.len(), "{lines}");
        let shown = format!("{:?}", script::evaluate_clean("part.die", &tube(lines)));
        for case in cases {
            assert!(shown.contains(case), "{lines}: no {case:?} in quality");
        }
    }
    // A cover by a name no cover has, or twice.
    script::assert_plate_refused(&[(
        "remove off = { cover: \"lid\" }",
        "`remove off`: the removal finds no cover `lid`",
    )]);
    let twice = script::diagnostics_of(
        "part.die",
        &tube("remove a = { cover: \"lid\" }\n    remove b = { cover: \"lid\" }"),
    );
    assert!(
        twice
            .iter()
            .any(|d| d.message.contains("finds cover `lid` removed already")),
        "{twice:?}"
    );
}

/// Covers that cannot be made are refused at the cover, saying why: a flange that is
/// not there, one named twice, far edges not in one plane, a flange joined to another
/// at a corner, and an `on` that is not two names.
#[test]
fn covers_that_cannot_be_made_are_refused() {
    let walls = "flange right = { at: (100, 30), height: 20 mm }\n    flange left = { at: (0, 30), height: 20 mm }";
    script::assert_plate_refused(&[
        (
            &format!("{walls}\n    cover lid = {{ on: [\"right\", \"top\"] }}"),
            "`cover lid`: the cover finds no flange `top`",
        ),
        (
            &format!("{walls}\n    cover lid = {{ on: [\"right\", \"right\"] }}"),
            "names flange `right` twice",
        ),
        (
            "flange right = { at: (100, 30), height: 20 mm }\n    flange left = { at: (0, 30), height: 25 mm, angle: 60 deg }\n    flange front = { from: (10, 0), to: (90, 0), height: 10 mm }\n    cover lid = { on: [\"front\", \"left\"] }",
            "would not be flat: the two far edges do not lie in one plane",
        ),
        (
            "flange right = { at: (100, 30), height: 20 mm }\n    flange front = { at: (50, 0), height: 20 mm }\n    flange left = { at: (0, 30), height: 20 mm }\n    cover lid = { on: [\"right\", \"left\"] }",
            "cannot stand on flange `right`: it is joined to another at a corner",
        ),
        (
            &format!("{walls}\n    cover lid = {{ on: \"right\" }}"),
            "a list of two flanges' names",
        ),
    ]);
}
