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

/// Rounds that pick no joint, two joints, a joint rounded already, or a flange of its
/// own thickness are refused at the round, naming the joint.
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
            "flange lip = { at: (100, 30), height: 20 mm }\n    flange front = { at: (50, 0), height: 20 mm }\n    round r = { at: (100, 0), radius: 2 mm }",
            "`round r`: the round picks no one joint: its point lies as near the foot of flange `lip` as the foot of flange `front`",
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
