//! Rounds (issue 15: "round the edge where two sheets meet, with a radius"): a joint,
//! a flange's foot or a bend's line, picked by a point near it and given an inside
//! radius after the fact. The part is the one the flange's or the bend's own `radius`
//! makes, to the last bit; the picks that do not fit are refused at the round.

#[path = "common/script.rs"]
mod script;

#[path = "common/sheet.rs"]
mod common;

use common::assert_sound;
use script::plate_script;

/// A round on a flange's foot and one on a bend's line make the part their radii make
/// when written on the flange and the bend: the same solid, point for point.
#[test]
fn a_round_is_the_radius_of_the_joint_it_picks() {
    let rounded = script::sheet_part(&plate_script(
        "flange lip = { at: (100, 30), height: 20 mm }
    bend leg = { from: (40, 0), to: (40, 60), angle: 60 deg }
    round lip_joint = { at: (100, 10), radius: 3 mm }
    round leg_joint = { at: (41, 50), radius: 4 mm }",
    ));
    let written = script::sheet_part(&plate_script(
        "flange lip = { at: (100, 30), height: 20 mm, radius: 3 mm }
    bend leg = { from: (40, 0), to: (40, 60), angle: 60 deg, radius: 4 mm }",
    ));
    assert_sound(&rounded.solid);
    assert_eq!(rounded.solid.positions(), written.solid.positions());
    assert_eq!(rounded.solid.faces(), written.solid.faces());
    assert_eq!(rounded.area, written.area);
    assert_eq!(rounded.volume, written.volume);
    let facets = rounded
        .solid
        .groups()
        .iter()
        .filter(|g| g.name().starts_with("lip.bend_") || g.name().starts_with("leg.bend_"))
        .count();
    assert!(facets > 10, "{facets} facet faces");
}

/// Rounds that pick no joint, a joint rounded already, a flange of its own thickness,
/// or a corner whose walls cannot run on round it (one bent on a radius) are refused at
/// the round, naming the joint.
#[test]
fn rounds_that_pick_no_roundable_joint_are_refused() {
    script::assert_plate_refused(&[
        (
            "flange lip = { at: (100, 30), height: 20 mm }\n    round r = { at: (50, 30), radius: 2 mm }",
            "`round r`: the round finds no joint within 5 mm of its point: the nearest, the foot of flange `lip`, lies 50 mm off",
        ),
        (
            "flange lip = { at: (100, 30), height: 20 mm, radius: 1 mm }\n    round r = { at: (100, 30), radius: 2 mm }",
            "`round r`: the round picks the foot of flange `lip`, which is rounded already, on a 1 mm radius",
        ),
        (
            "flange lip = { at: (100, 30), height: 20 mm, thickness: 2 mm }\n    round r = { at: (100, 30), radius: 2 mm }",
            "`round r`: the round picks the foot of flange `lip`, a flange of its own thickness",
        ),
        (
            "flange lip = { at: (100, 30), height: 20 mm, radius: 3 mm }\n    flange front = { at: (50, 0), height: 20 mm }\n    round r = { at: (100, 0), radius: 2 mm }",
            "`round r`: the round picks the corner where `lip` and `front` meet, and `lip` is bent on a radius, drawn, or of its own thickness",
        ),
        (
            "round r = { at: (100, 30), radius: 2 mm }",
            "`round r`: the round finds no joint to round: the part has no flange and no bend",
        ),
        (
            "flange lip = { at: (100, 30), height: 20 mm }\n    round r = { at: (100, 30), radius: 0 mm }",
            "`round r`: the round radius must be above 0, not 0",
        ),
    ]);
}

/// A round at the corner where two walls meet (two flanges joined there, or a flange
/// run round the outline): the outline's corner rounded in plan on the radius, chords
/// within 0.05 mm of the arc, and the walls running on round it as strips on the
/// chords, each joined to the next. The plate keeps its rounded outline's area, the
/// walls their feet's length times their height, and the solid is sound, its volume
/// the area times the thickness but for the t³ corners.
#[test]
fn rounding_the_corner_where_two_walls_meet_rounds_it_in_plan() {
    let walls = [
        "flange a = { at: (50, 0), height: 20 mm }\n    flange b = { at: (100, 30), height: 20 mm }",
        "flange a = { at: (50, 0), height: 20 mm, angle: 80 deg }\n    flange b = { at: (100, 30), height: 20 mm, angle: 80 deg }",
        "flange wall = { around: true, height: 20 mm }",
    ];
    for lines in walls {
        let part = script::sheet_part(&script::plate_script(&format!(
            "{lines}\n    round corner = {{ at: (100, 0), radius: 10 mm }}"
        )));
        common::assert_sound(&part.solid);
        // The corner's strips (named after the round, or the run's) stand on the arc's
        // chords: the floor's corner points lie on the arc.
        let strips = part
            .solid
            .groups()
            .iter()
            .filter(|g| g.name().ends_with(".inside"))
            .filter(|g| g.name().starts_with("corner.") || g.name().starts_with("wall."))
            .count();
        assert!(strips >= 4, "{lines}: {strips} strips");
        let centre = glam::DVec3::new(90.0, 10.0, 0.0);
        let on_arc = part
            .mid_mesh
            .positions()
            .iter()
            .filter(|p| p.z.abs() < 1e-9 && p.x > 90.0 && p.y < 10.0)
            .all(|p| (p.distance(centre) - 10.0).abs() < 1e-9);
        assert!(on_arc, "{lines}: a floor corner off the arc");
        // Each joint between two strips adds at most t³/4 (a square corner's).
        let joints = (strips + 2) as f64;
        assert!(
            (part.volume - part.area).abs() < joints * 0.25,
            "{lines}: {} against {}",
            part.volume,
            part.area
        );
    }
}

/// Corner rounds that cannot be made are refused at the round: walls of different
/// heights, and a radius the edges cannot hold.
#[test]
fn corner_rounds_that_cannot_be_made_are_refused() {
    script::assert_plate_refused(&[
        (
            "flange a = { at: (50, 0), height: 20 mm }\n    flange b = { at: (100, 30), height: 25 mm }\n    round corner = { at: (100, 0), radius: 10 mm }",
            "`round corner`: the round picks the corner where `a` and `b` meet, which stand at different heights or angles",
        ),
        (
            "flange a = { at: (50, 0), height: 20 mm }\n    flange b = { at: (100, 30), height: 20 mm }\n    round corner = { at: (100, 0), radius: 70 mm }",
            "`round corner`: the round radius 70 mm does not fit the corner: it takes 70 mm of each edge",
        ),
    ]);
}
