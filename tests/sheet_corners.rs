//! Closed corners (issue 15: "three or more zero-area loops meeting at one vertex",
//! "three sheets at a corner"): two flanges on the two edges at a corner of the plate
//! are joined on the line where their planes cross, so the plate and the two flanges
//! meet at the corner's vertex. Checked on trays whose solids are known in closed form
//! (the space between an outer and an inner prism), and on the refusals.

#[path = "common/script.rs"]
mod script;

#[path = "common/sheet.rs"]
mod common;

use std::collections::BTreeSet;

use common::{assert_sound, volume};
use dieface::sheet::junction::{meetings, JunctionType, Meeting};
use dieface::sheet::part::SheetPart;
use dieface::sheet::topology::{FaceRole, Sheet, VertexId};
use glam::DVec3;

const T: f64 = 1.0;
const H: f64 = 20.0;

/// A script of a plate over `outline` (points in the top view, 1 mm thick) with
/// `lines` in its block.
fn plate(outline: &[(f64, f64)], lines: &str) -> String {
    let mut s = String::from("units mm deg\nsheet tray {\n    outline = sketch(top) { ");
    for (i, (x, y)) in outline.iter().enumerate() {
        s += &if i == 0 {
            format!("from ({x}, {y}); ")
        } else {
            format!("line to ({x}, {y}); ")
        };
    }
    s + &format!("close }}\n    thickness = 1 mm\n{lines}}}\n")
}

/// A script of a plate over `outline` with a flange on every edge, each given `fields`
/// after its `at` (the edge's midpoint).
fn tray(outline: &[(f64, f64)], fields: &dyn Fn(usize) -> String) -> String {
    let n = outline.len();
    let mut lines = String::new();
    for i in 0..n {
        let (a, c) = (outline[i], outline[(i + 1) % n]);
        let at = (0.5 * (a.0 + c.0), 0.5 * (a.1 + c.1));
        lines += &format!(
            "    flange wall_{} = {{ at: ({}, {}), {} }}\n",
            i + 1,
            at.0,
            at.1,
            fields(i)
        );
    }
    plate(outline, &lines)
}

/// How many sheets have a side at vertex `v`.
fn sheets_at(sheet: &Sheet, v: VertexId) -> usize {
    let b = &sheet.brep;
    let mut sheets = BTreeSet::new();
    for f in b.faces() {
        let FaceRole::Side { twin } = sheet.face_role(f).unwrap() else {
            continue;
        };
        let on = b.loops_of(f).unwrap().iter().any(|&l| {
            b.loop_halves(l)
                .unwrap()
                .into_iter()
                .any(|h| b.vertex(h).unwrap() == v)
        });
        if on {
            sheets.insert(f.min(twin));
        }
    }
    sheets.len()
}

/// The vertex of the sheet model at `p` (either of a twin pair).
fn vertex_at(part: &SheetPart, p: DVec3) -> VertexId {
    part.sheet
        .brep
        .vertices()
        .find(|&v| part.mid.point(v).is_some_and(|q| q.distance(p) < 1e-9))
        .unwrap_or_else(|| panic!("no vertex at {p}"))
}

fn has_point(part: &SheetPart, p: DVec3) -> bool {
    part.solid.positions().iter().any(|q| q.distance(p) < 1e-9)
}

/// The area of a polygon offset by `d` (out, below 0 in) with mitred corners: its area,
/// plus its perimeter times d, plus d² times the sum over its corners of the tangent of
/// half the turn there (1 at a square convex corner, -1 at a square reflex one).
fn offset_area(outline: &[(f64, f64)], d: f64) -> f64 {
    let n = outline.len();
    let p = |i: usize| DVec3::new(outline[i % n].0, outline[i % n].1, 0.0);
    let (mut area, mut perimeter, mut turns) = (0.0, 0.0, 0.0);
    for i in 0..n {
        let (a, b, c) = (p(i), p(i + 1), p(i + 2));
        area += 0.5 * a.cross(b).z;
        perimeter += a.distance(b);
        let (u, w) = ((b - a).normalize(), (c - b).normalize());
        let turn = u.cross(w).z.atan2(u.dot(w));
        turns += (0.5 * turn).tan();
    }
    area + perimeter * d + turns * d * d
}

/// A box tray (a 100 x 60 plate, four square walls 20 mm high): at each bottom corner
/// three sheets meet, each pair along an edge, and no thickness face reaches it; the
/// solid's corner there is where three offset planes meet, (t/2, t/2, t/2) from the
/// corner inside and the same outside. The solid is the outer box less the inner one:
/// A t + t³, exactly. At each top corner two walls meet on the free boundary, the
/// paper's plain mitre: α = β = θ = 90 deg, φ = 0, type 1.
#[test]
fn a_box_tray_is_three_sheets_at_each_bottom_corner() {
    let outline = [(0.0, 0.0), (100.0, 0.0), (100.0, 60.0), (0.0, 60.0)];
    let part = script::sheet_part(&tray(&outline, &|_| format!("height: {H} mm")));
    assert_sound(&part.solid);
    let area = 100.0 * 60.0 + 2.0 * (100.0 + 60.0) * H;
    assert!((part.area - area).abs() < 1e-9 * area, "{}", part.area);
    let exact = (100.0 + T) * (60.0 + T) * (H + T / 2.0) - (100.0 - T) * (60.0 - T) * (H - T / 2.0);
    assert!((exact - (area * T + T * T * T)).abs() < 1e-9);
    assert!(
        (volume(&part.solid) - exact).abs() < 1e-9 * exact,
        "{} against {exact}",
        volume(&part.solid)
    );
    let mut found = meetings(&part.sheet, &part.mid).unwrap();
    found.sort_by(|x, y| format!("{x:?}").cmp(&format!("{y:?}")));
    assert_eq!(
        found.len(),
        4,
        "only the top corners are on the free boundary"
    );
    for &(x, y) in &outline {
        let v = vertex_at(&part, DVec3::new(x, y, 0.0));
        assert_eq!(sheets_at(&part.sheet, v), 3, "at ({x}, {y})");
        let (sx, sy) = (
            if x == 0.0 { 1.0 } else { -1.0 },
            if y == 0.0 { 1.0 } else { -1.0 },
        );
        let inside = DVec3::new(x + sx * T / 2.0, y + sy * T / 2.0, T / 2.0);
        let outside = DVec3::new(x - sx * T / 2.0, y - sy * T / 2.0, -T / 2.0);
        assert!(
            has_point(&part, inside) && has_point(&part, outside),
            "at ({x}, {y})"
        );
        let top = DVec3::new(x, y, H);
        let j = part
            .junctions
            .iter()
            .find(|j| j.at.distance(top) < 1e-9)
            .unwrap_or_else(|| panic!("no junction at {top}"));
        let right = std::f64::consts::FRAC_PI_2;
        for (angle, expected) in [
            (j.alpha, right),
            (j.beta, right),
            (j.theta, right),
            (j.phi, 0.0),
        ] {
            assert!((angle - expected).abs() < 1e-9, "{j:?}");
        }
        assert_eq!(j.kind, JunctionType::One);
        assert!(found.iter().all(|m| matches!(m, Meeting::Two(_))));
    }
}

/// Walls of their own thickness at a corner (the right wall 1.5 mm, the rest 1 mm):
/// each side still moves out by half its own sheet's thickness, so the solid is the
/// outer box less the inner one with the right wall's faces 0.75 mm off its mid-plane.
#[test]
fn walls_of_two_gauges_meet_at_a_closed_corner() {
    let outline = [(0.0, 0.0), (100.0, 0.0), (100.0, 60.0), (0.0, 60.0)];
    let part = script::sheet_part(&tray(&outline, &|i| {
        if i == 1 {
            format!("height: {H} mm, thickness: 1.5 mm")
        } else {
            format!("height: {H} mm")
        }
    }));
    assert_sound(&part.solid);
    let exact = (100.0 + 0.5 + 0.75) * (60.0 + T) * (H + T / 2.0)
        - (100.0 - 0.5 - 0.75) * (60.0 - T) * (H - T / 2.0);
    assert!(
        (volume(&part.solid) - exact).abs() < 1e-9 * exact,
        "{} against {exact}",
        volume(&part.solid)
    );
    assert!(has_point(&part, DVec3::new(100.75, -0.5, -0.5)));
    assert!(has_point(&part, DVec3::new(99.25, 0.5, 0.5)));
}

/// An L-shaped tray: at the L's inside (reflex) corner the walls meet on the inside of
/// the turn. The solid is the outline offset out by t/2 over the full height less the
/// outline offset in by t/2 above the plate's top, each offset area in closed form.
#[test]
fn an_l_shaped_tray_closes_its_inside_corner_too() {
    let outline = [
        (0.0, 0.0),
        (80.0, 0.0),
        (80.0, 30.0),
        (30.0, 30.0),
        (30.0, 70.0),
        (0.0, 70.0),
    ];
    let part = script::sheet_part(&tray(&outline, &|_| format!("height: {H} mm")));
    assert_sound(&part.solid);
    let exact = offset_area(&outline, T / 2.0) * (H + T / 2.0)
        - offset_area(&outline, -T / 2.0) * (H - T / 2.0);
    assert!(
        (volume(&part.solid) - exact).abs() < 1e-9 * exact,
        "{} against {exact}",
        volume(&part.solid)
    );
    let reflex = vertex_at(&part, DVec3::new(30.0, 30.0, 0.0));
    assert_eq!(sheets_at(&part.sheet, reflex), 3);
    assert!(has_point(&part, DVec3::new(30.5, 30.5, -0.5)));
    assert!(has_point(&part, DVec3::new(29.5, 29.5, 0.5)));
}

/// A drafted tray (walls at 80 deg to the plate, leaning out 10 deg): each wall is cut
/// on the mitre line, the line through the corner where the two walls' planes cross,
/// and its far corner lies there at the walls' common height above the plate, 20 sin
/// 80 deg.
#[test]
fn drafted_walls_are_cut_on_the_mitre_line() {
    let outline = [(0.0, 0.0), (100.0, 0.0), (100.0, 60.0), (0.0, 60.0)];
    let angle = 80f64.to_radians();
    let part = script::sheet_part(&tray(&outline, &|_| {
        format!("height: {H} mm, angle: 80 deg")
    }));
    assert_sound(&part.solid);
    // At the corner (0, 0) the front wall rises along (0, -cos 80, sin 80) and the left
    // along (-cos 80, 0, sin 80): they meet 20 mm up each, at the far corner.
    let lean = H * angle.cos();
    let top = DVec3::new(-lean, -lean, H * angle.sin());
    let v = vertex_at(&part, top);
    assert_eq!(sheets_at(&part.sheet, v), 2);
    assert_eq!(
        sheets_at(&part.sheet, vertex_at(&part, DVec3::ZERO)),
        3,
        "three sheets at the corner"
    );
    // Every face of the solid lies in one plane (the build refuses warped faces), and
    // the mid-surface's area is the plate's plus four trapezoids.
    let slant = H;
    let walls = 2.0 * (100.0 + 100.0 + 2.0 * lean) / 2.0 * slant
        + 2.0 * (60.0 + 60.0 + 2.0 * lean) / 2.0 * slant;
    let area = 6000.0 + walls;
    assert!(
        (part.area - area).abs() < 1e-9 * area,
        "{} against {area}",
        part.area
    );
}

/// Flanges that cannot be joined at their corner are refused there, naming both: walls
/// standing at different heights (their far edges would not meet), a wall with a bend
/// radius (its corner would need a curved piece), and two flanges side by side on one
/// edge (in one plane, with no mitre line).
#[test]
fn flanges_that_cannot_be_joined_are_refused_at_the_corner() {
    for (flanges, expected) in [
        (
            "flange front = { at: (50, 0), height: 20 mm }\n    flange right = { at: (100, 30), height: 25 mm }",
            "they stand 20 mm and 25 mm above the plate at the corner",
        ),
        (
            "flange front = { at: (50, 0), height: 20 mm, radius: 2 mm }\n    flange right = { at: (100, 30), height: 20 mm }",
            "a flange with a bend radius cannot be joined at a corner yet",
        ),
        (
            "flange one = { from: (0, 0), to: (50, 0), height: 20 mm }\n    flange two = { from: (50, 0), to: (100, 0), height: 20 mm }",
            "they stand in one plane there",
        ),
    ] {
        let found = script::diagnostics_of("part.die", &script::plate_script(flanges));
        let [d] = &found[..] else {
            panic!("{expected}: {found:?}")
        };
        assert!(
            d.message.contains(expected) && d.message.contains("cannot be joined there"),
            "{expected}: {}",
            d.message
        );
        assert_eq!(d.secondary.len(), 1, "both flanges are pointed at");
    }
}

/// A flange from a point on one edge to a point on another runs along the outline
/// between them, counter-clockwise: one strip per edge, `NAME.1`, `NAME.2`, ..., each
/// joined to the next at the corner between them. From (30, 0) round to (60, 60) on
/// the 100 x 60 plate: 70 + 60 + 40 mm of wall, two closed corners (t³/4 each).
#[test]
fn a_flange_from_one_edge_to_another_runs_along_the_outline_between() {
    let part = script::sheet_part(&script::plate_script(
        "flange lip = { from: (30, 0), to: (60, 60), height: 20 mm }",
    ));
    assert_sound(&part.solid);
    let area = 6000.0 + (70.0 + 60.0 + 40.0) * H;
    assert!((part.area - area).abs() < 1e-9 * area, "{}", part.area);
    let exact = area * T + 2.0 * T * T * T / 4.0;
    assert!(
        (part.volume - exact).abs() < 1e-9 * exact,
        "{} against {exact}",
        part.volume
    );
    let names: Vec<&str> = part.solid.groups().iter().map(|g| g.name()).collect();
    for strip in ["lip.1.inside", "lip.2.inside", "lip.3.outside"] {
        assert!(names.contains(&strip), "no {strip} in {names:?}");
    }
    assert_eq!(
        sheets_at(&part.sheet, vertex_at(&part, DVec3::new(100.0, 0.0, 0.0))),
        3
    );
}

/// A wall `around` a chamfered rectangle (an octagon): every corner closed, so the
/// solid is the outline offset out by t/2 over the full height less the outline
/// offset in by t/2 above the floor, exactly, at the 45 deg corners as at square ones.
#[test]
fn a_wall_around_an_octagon_is_the_shell_between_its_prisms() {
    let outline = [
        (10.0, 0.0),
        (90.0, 0.0),
        (100.0, 10.0),
        (100.0, 50.0),
        (90.0, 60.0),
        (10.0, 60.0),
        (0.0, 50.0),
        (0.0, 10.0),
    ];
    let part = script::sheet_part(&plate(
        &outline,
        "    flange wall = { around: true, height: 20 mm }\n",
    ));
    assert_sound(&part.solid);
    let exact = offset_area(&outline, T / 2.0) * (H + T / 2.0)
        - offset_area(&outline, -T / 2.0) * (H - T / 2.0);
    assert!(
        (part.volume - exact).abs() < 1e-9 * exact,
        "{} against {exact}",
        part.volume
    );
    assert_eq!(strips(&part), 8);
    assert!(part.junctions.iter().all(|j| j.at.z == H));
}

/// A drafted wall `around` a rectangle with 15 mm corner fillets: a drawn tray with
/// round corners in plan, each fillet's chords a strip of its own joined to the next on
/// the mitre line, so the rim runs level at 25 sin 80 deg all round and the solid is
/// sound.
#[test]
fn a_drafted_wall_around_a_filleted_outline_is_a_tray_with_round_corners() {
    let part = script::sheet_part(&drafted_tray(""));
    assert_sound(&part.solid);
    assert_rim_level(&part);
    let strips = strips(&part);
    assert!(strips > 4 * 4, "{strips} strips");
    assert_eq!(
        part.junctions.len(),
        strips,
        "one junction at each rim corner"
    );
}

/// An open corner: each wall of a box ended 2 mm short of the corners with `from` and
/// `to` (a corner relief), so no two are joined. Each wall's end then stands on the
/// plate's edge as a flange on part of an edge does: junction type 2 at all eight
/// ends, the wall's outside half its thickness proud of the plate's edge with a step.
/// The solid is sound and, the steps' corners cancelling, the area times t.
#[test]
fn walls_ended_short_of_the_corners_leave_them_open() {
    let part = script::sheet_part(&script::plate_script(
        "flange front = { from: (2, 0), to: (98, 0), height: 20 mm }\n    flange right = { from: (100, 2), to: (100, 58), height: 20 mm }\n    flange back = { from: (98, 60), to: (2, 60), height: 20 mm }\n    flange left = { from: (0, 58), to: (0, 2), height: 20 mm }",
    ));
    assert_sound(&part.solid);
    let area = 6000.0 + 2.0 * (96.0 + 56.0) * H;
    assert!((part.area - area).abs() < 1e-9 * area, "{}", part.area);
    assert!(
        (part.volume - area * T).abs() < 1e-9 * area,
        "{} against {}",
        part.volume,
        area * T
    );
    assert_eq!(part.junctions.len(), 8);
    assert!(part.junctions.iter().all(|j| j.kind == JunctionType::Two));
    for &(x, y) in &[(0.0, 0.0), (100.0, 0.0), (100.0, 60.0), (0.0, 60.0)] {
        let v = vertex_at(&part, DVec3::new(x, y, 0.0));
        assert_eq!(
            sheets_at(&part.sheet, v),
            1,
            "the plate alone at ({x}, {y})"
        );
    }
}

/// A flange `around` the outline takes no point, and a run of edges is sharp.
#[test]
fn runs_that_cannot_be_made_are_refused() {
    script::assert_plate_refused(&[
        (
            "flange wall = { around: true, at: (50, 0), height: 20 mm }",
            "`flange wall` runs `around` the whole outline, so it takes no `at`",
        ),
        (
            "flange wall = { from: (30, 0), to: (60, 60), height: 20 mm, radius: 2 mm }",
            "`flange wall`: the flange runs along several edges, so it must be sharp",
        ),
    ]);
}

/// A box tray with a level brim 10 mm wide all round its rim (a return flange on the
/// wall run, turned 90 deg away from the inside): four sheets meet at each rim corner
/// (two walls and two brim strips, every pair along an edge), the brim strips joined
/// on the line halving the corner in their plane, so the brim's corner is square. The
/// solid's corner there is where four offset planes meet, one inside and one outside.
/// In closed form, slice by slice: the floor (100 + t)(60 + t) t, the walls' ring
/// between z = t/2 and H - t/2, and at the rim the ring between the brim's 120 x 80
/// outline and the walls' inside: the area times t exactly (the rim's saddle corners
/// give back what the floor's corners add).
#[test]
fn a_brim_round_a_box_tray_is_four_sheets_at_each_rim_corner() {
    let outline = [(0.0, 0.0), (100.0, 0.0), (100.0, 60.0), (0.0, 60.0)];
    let part = script::sheet_part(&plate(
        &outline,
        "    flange wall = { around: true, height: 20 mm }
    flange brim = { on: \"wall\", height: 10 mm, angle: -90 deg }
",
    ));
    assert_sound(&part.solid);
    let area = 6000.0 + 2.0 * (100.0 + 60.0) * H + (120.0 * 80.0 - 6000.0);
    assert!((part.area - area).abs() < 1e-9 * area, "{}", part.area);
    let rim = (120.0 * 80.0 - (100.0 - T) * (60.0 - T)) * T;
    let exact = box_below_rim() + rim;
    assert!((exact - area * T).abs() < 1e-9 * exact);
    assert!(
        (part.volume - exact).abs() < 1e-9 * exact,
        "{} against {exact}",
        part.volume
    );
    for &(x, y) in &outline {
        let v = vertex_at(&part, DVec3::new(x, y, H));
        assert_eq!(sheets_at(&part.sheet, v), 4, "at ({x}, {y}, {H})");
        let (sx, sy) = (
            if x == 0.0 { 1.0 } else { -1.0 },
            if y == 0.0 { 1.0 } else { -1.0 },
        );
        let inside = DVec3::new(x + sx * T / 2.0, y + sy * T / 2.0, H + T / 2.0);
        let outside = DVec3::new(x - sx * T / 2.0, y - sy * T / 2.0, H - T / 2.0);
        assert!(
            has_point(&part, inside) && has_point(&part, outside),
            "at ({x}, {y})"
        );
        // The brim's square outer corner, where two strips in one plane meet on the
        // free boundary: type 1 (the sheets are the mid-surfaces), whatever the angles.
        let corner = DVec3::new(x - sx * 10.0, y - sy * 10.0, H);
        let j = part
            .junctions
            .iter()
            .find(|j| j.at.distance(corner) < 1e-9)
            .unwrap_or_else(|| panic!("no junction at {corner}"));
        assert_eq!(j.kind, JunctionType::One, "{j:?}");
        assert!(has_point(&part, corner + DVec3::new(0.0, 0.0, T / 2.0)));
    }
    let names: Vec<&str> = part.solid.groups().iter().map(|g| g.name()).collect();
    for face in ["brim.1.inside", "brim.4.outside", "wall.2.inside"] {
        assert!(names.contains(&face), "no {face} in {names:?}");
    }
}

/// A lip turned in 10 mm over the box tray all round (the return at +90 deg): the
/// strips meet on the line halving each corner, so the opening left is the 80 x 40
/// rectangle, and the solid's rim slice is the ring between the walls' outside and that
/// opening: A t + 2 t³ in all.
#[test]
fn a_lip_turned_in_round_a_box_tray_leaves_a_rectangular_opening() {
    let outline = [(0.0, 0.0), (100.0, 0.0), (100.0, 60.0), (0.0, 60.0)];
    let part = script::sheet_part(&plate(
        &outline,
        "    flange wall = { around: true, height: 20 mm }
    flange lip = { on: \"wall\", height: 10 mm, angle: 90 deg }
",
    ));
    assert_sound(&part.solid);
    let rim = ((100.0 + T) * (60.0 + T) - 80.0 * 40.0) * T;
    let exact = box_below_rim() + rim;
    assert!(
        (part.volume - exact).abs() < 1e-9 * exact,
        "{} against {exact}",
        part.volume
    );
    assert!(has_point(&part, DVec3::new(10.0, 10.0, H + T / 2.0)));
    assert!(has_point(&part, DVec3::new(90.0, 50.0, H - T / 2.0)));
}

/// A level brim round the drafted tray with round corners (walls at 80 deg, 15 mm
/// fillets in plan): a strip on each wall strip, each joined to the next in the rim's
/// plane, the rim flat at 25 sin 80 deg and its outer edge the walls' top offset 12 mm
/// out. The solid is sound, and its volume is the area times t to 1e-9: round the rim
/// the corners' saddles give back what the floor's corners add, as on the box.
#[test]
fn a_brim_round_a_drafted_tray_with_round_corners_lies_level() {
    let part = script::sheet_part(&drafted_tray(
        "    flange brim = { on: \"wall\", height: 12 mm, angle: -80 deg }\n",
    ));
    assert_sound(&part.solid);
    assert_rim_level(&part);
    assert!(
        (part.volume - part.area * T).abs() < 1e-9 * part.volume,
        "{} against {}",
        part.volume,
        part.area * T
    );
    assert!(part.junctions.iter().all(|j| j.kind == JunctionType::One));
}

/// Returns that cannot be joined at a corner are refused at the return: one on a wall
/// joined to a wall with none (the corner's four sheets would not close), brim strips
/// of different widths in one plane, and a brim on a bend radius at a joined corner.
#[test]
fn returns_that_cannot_be_joined_are_refused() {
    script::assert_plate_refused(&[
        (
            "flange lip = { at: (100, 30), height: 20 mm }
    flange side = { at: (50, 0), height: 20 mm }
    flange turn = { on: \"lip\", height: 10 mm }",
            "`flange turn`: the flange cannot end at (100, 0, 20) where flange `lip` is joined to another at a corner",
        ),
        (
            "flange lip = { at: (100, 30), height: 20 mm }
    flange side = { at: (50, 0), height: 20 mm }
    flange a = { on: \"lip\", height: 10 mm, angle: -90 deg }
    flange b = { on: \"side\", height: 8 mm, angle: -90 deg }",
            "they stand in one plane and reach 10 mm and 8 mm from their edges",
        ),
        (
            "flange wall = { around: true, height: 20 mm }
    flange brim = { on: \"wall\", height: 10 mm, angle: -90 deg, radius: 2 mm }",
            "cannot have a bend radius on flange `wall.1`, which is joined to another at a corner",
        ),
    ]);
}

/// The 100 x 60 box tray's solid below its rim's slice (z up to H - t/2): the floor's
/// slice, (100 + t)(60 + t) t, and the walls' ring between z = t/2 and H - t/2.
fn box_below_rim() -> f64 {
    let floor = (100.0 + T) * (60.0 + T) * T;
    floor + ((100.0 + T) * (60.0 + T) - (100.0 - T) * (60.0 - T)) * (H - T)
}

/// A 160 x 100 tray with 15 mm corner fillets in plan and a wall `around` it 25 mm up at
/// 80 deg, 1 mm thick, with `lines` added to its block.
fn drafted_tray(lines: &str) -> String {
    format!(
        "units mm deg
sheet tray {{
    outline = sketch(top) {{ from (0, 0); line to (160, 0); fillet 15; line to (160, 100); fillet 15; line to (0, 100); fillet 15; close; fillet 15 }}
    thickness = 1 mm
    flange wall = {{ around: true, height: 25 mm, angle: 80 deg }}
{lines}}}"
    )
}

/// Every mid-surface point of [`drafted_tray`] off the floor lies on its rim, level at
/// 25 sin 80 deg.
fn assert_rim_level(part: &SheetPart) {
    let rim = 25.0 * 80f64.to_radians().sin();
    let high: Vec<f64> = part
        .mid_mesh
        .positions()
        .iter()
        .map(|p| p.z)
        .filter(|&z| z > 1.0)
        .collect();
    assert!(high.iter().all(|&z| (z - rim).abs() < 1e-9), "{high:?}");
}

/// How many strips a flange `wall` along a run of edges has: its faces `wall.K.inside`.
fn strips(part: &SheetPart) -> usize {
    part.solid
        .groups()
        .iter()
        .filter(|g| g.name().starts_with("wall.") && g.name().ends_with(".inside"))
        .count()
}
