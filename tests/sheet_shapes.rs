//! Sheets added on a picked edge with drawn boundary curves (issue 15: "add a sheet on
//! a working plane given by ... one edge and an angle to the existing sheet, with 2-D
//! boundary curves that close a loop with the picked edges"): a flange's `shape`,
//! drawn in its own plane, and the edge picked by a point near it. Checked on shapes
//! whose areas are known, and on the bad inputs the issue lists: curves that do not
//! close a loop with the picked edge, and a picked edge that is not on the sheet.

#[path = "common/script.rs"]
mod script;

#[path = "common/sheet.rs"]
mod common;

use common::assert_sound;
use dieface::sheet::part::SheetPart;
use glam::DVec3;
use script::plate_script;

fn has_mid_point(part: &SheetPart, p: DVec3) -> bool {
    part.mid_mesh
        .positions()
        .iter()
        .any(|q| q.distance(p) < 1e-9)
}

/// A tab drawn square at its ends and chamfered above (on part of the front edge) and
/// an ear on the whole right edge, each leaning as its `angle` says: the mid-surface
/// is the plate and the two drawn polygons, each corner where the shape puts it in the
/// flange's plane, and the solid holds the area times the thickness, exactly.
#[test]
fn a_drawn_shape_is_the_flange_outline_in_its_own_plane() {
    let part = script::sheet_part(&plate_script(
        "flange tab = { from: (20, 0), to: (60, 0), shape: sketch(profile) { from (0, 0); line to (0, 10); line to (10, 20); line to (30, 20); line to (40, 10); line to (40, 0) } }
    flange ear = { at: (100, 30), angle: 60 deg, shape: sketch(profile) { from (0, 0); line to (0, 8); line to (60, 8); line to (60, 0) } }",
    ));
    assert_sound(&part.solid);
    let tab = 40.0 * 10.0 + (40.0 + 20.0) / 2.0 * 10.0;
    let ear = 60.0 * 8.0;
    let area = 6000.0 + tab + ear;
    assert!((part.area - area).abs() < 1e-9 * area, "{}", part.area);
    assert!(
        (part.volume - area * 1.0).abs() < 1e-9 * area,
        "{}",
        part.volume
    );
    // Seen from outside the front edge, s runs from (20, 0) to (60, 0), z straight up.
    for (s, z) in [(0.0, 10.0), (10.0, 20.0), (30.0, 20.0), (40.0, 10.0)] {
        let p = DVec3::new(20.0 + s, 0.0, z);
        assert!(has_mid_point(&part, p), "no tab corner at {p}");
    }
    // Seen from outside the right edge, s runs from (100, 0) to (100, 60); the ear
    // leans out at 60 deg: z up it is (cos 60, 0, sin 60) per mm.
    let a = 60f64.to_radians();
    for s in [0.0, 60.0] {
        let p = DVec3::new(100.0 + 8.0 * a.cos(), s, 8.0 * a.sin());
        assert!(has_mid_point(&part, p), "no ear corner at {p}");
    }
    let names: Vec<&str> = part.solid.groups().iter().map(|g| g.name()).collect();
    assert!(names.contains(&"tab.inside") && names.contains(&"ear.outside"));
}

/// Curves are followed by straight edges within 0.05 mm, as an outline's are: a tab
/// with a round top (a half circle of radius 20 on a 40 x 15 rectangle) has the
/// rectangle's area plus the half circle's, less at most the chords' share.
#[test]
fn a_round_topped_tab_follows_its_arc() {
    let part = script::sheet_part(&plate_script(
        "flange tab = { from: (20, 0), to: (60, 0), shape: sketch(profile) { from (0, 0); line to (0, 15); arc to (40, 15) through (20, 35); line to (40, 0) } }",
    ));
    assert_sound(&part.solid);
    let exact = 6000.0 + 40.0 * 15.0 + std::f64::consts::PI * 400.0 / 2.0;
    let arc = std::f64::consts::PI * 20.0;
    assert!(
        part.area < exact && exact - part.area < 0.05 * arc,
        "{} against {exact}",
        part.area
    );
    // The top of the arc is a vertex, 35 mm up at the tab's middle.
    assert!(has_mid_point(&part, DVec3::new(40.0, 0.0, 35.0)));
}

/// The bad inputs, each refused at the flange with what is wrong.
#[test]
fn shapes_and_picks_that_do_not_fit_are_refused() {
    script::assert_plate_refused(&[
        (
            "flange tab = { at: (50, 0), shape: sketch(profile) { from (5, 0); line to (5, 10); line to (100, 10); line to (100, 0) } }",
            "the flange is drawn to start at (5, 0), not at the edge's left end (0, 0): its boundary curves must close a loop with the edge",
        ),
        (
            "flange tab = { at: (50, 0), shape: sketch(profile) { from (0, 0); line to (0, 10); line to (90, 10); line to (90, 0) } }",
            "the flange is drawn to end at (90, 0), not at the edge's right end (100, 0) (the edge is 100 mm long)",
        ),
        (
            "flange tab = { at: (50, 0), shape: sketch(profile) { from (0, 0); line to (0, 10); line to (50, 0); line to (100, 10); line to (100, 0) } }",
            "the flange is drawn down to the edge (or below it) at (50, 0)",
        ),
        (
            "flange tab = { at: (50, 0), shape: sketch(profile) { from (0, 0); line to (60, 10); line to (40, 10); line to (100, 0) } }",
            "the flange is drawn crossing itself",
        ),
        (
            "flange tab = { at: (50, 0), shape: sketch(profile) { from (0, 0); line to (0, 10); line to (100, 10); line to (100, 0); close } }",
            "must be an open sketch in the `profile` view, not a closed sketch",
        ),
        (
            "flange tab = { at: (50, 0), shape: sketch(top) { from (0, 0); line to (0, 10); line to (100, 10); line to (100, 0) } }",
            "must be an open sketch in the `profile` view, not a sketch in the top view",
        ),
        (
            "flange tab = { at: (50, 0), height: 10 mm, shape: sketch(profile) { from (0, 0); line to (0, 10); line to (100, 10); line to (100, 0) } }",
            "has both a `height` and a `shape`",
        ),
        (
            "flange tab = { at: (50, 0), radius: 2 mm, shape: sketch(profile) { from (0, 0); line to (0, 10); line to (100, 10); line to (100, 0) } }",
            "cannot have both a drawn `shape` and a bend radius yet",
        ),
        (
            "flange tab = { at: (50, 0), shape: sketch(profile) { from (0, 0); line to (0, 10); line to (100, 10); line to (100, 0) } }\n    flange side = { at: (100, 30), height: 10 mm }",
            "a flange with a drawn `shape` cannot be joined at a corner yet",
        ),
        (
            "flange tab = { at: (50, -20), height: 10 mm }",
            "picks no edge of the sheet: its point (50, -20, 0) lies 20 mm from the nearest edge, and a picked edge must lie within 5 mm of its point",
        ),
        (
            "flange tab = { at: (100, 0), height: 10 mm }",
            "picks no one edge: its point (100, 0, 0) lies as near the edge from",
        ),
    ]);
}
