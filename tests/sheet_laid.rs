//! Sheet parts laid on a curved surface (`on = surface`): built flat in the outline's
//! view and laid onto the surface, each face cut to follow it. Checked against closed
//! forms on an exact (rational) cylinder, and on a doubly curved patch against the
//! kernel's own closest-point inversion, which finds points on the surface by another
//! road than the laying does.

#[path = "common/script.rs"]
mod script;

#[path = "common/sheet.rs"]
mod sheet;

use dieface::geom::inversion::closest_point_on_surface;
use dieface::geom::mesh::{crossings, Mesh};
use dieface::sheet::laid::LAID_TOLERANCE;
use dieface::sheet::part::SheetPart;
use glam::DVec3;
use script::{diagnostics_of, sheet_part};
use sheet::{assert_closed_and_oriented, volume};

/// The trough's radius (mm): an exact cylinder about the line y = 50, z = 10 - R,
/// along x, its top at z = 10.
const R: f64 = 200.0;

/// A script laying a sheet block's `lines` on the trough (x from -40 to 140, 30 deg
/// either side of its top), over a 100 x 100 plate at 1 mm.
fn trough_script(lines: &str) -> String {
    format!(
        "units mm deg\n\
         let r = {R} mm\n\
         let half = 30 deg\n\
         let row = fn(x) => [(x, 50 mm - r * sin(half), 10 mm - r + r * cos(half)), \
         (x, 50 mm, 10 mm - r + r / cos(half)), (x, 50 mm + r * sin(half), 10 mm - r + r * cos(half))]\n\
         sheet panel {{\n\
             outline = sketch(top) {{ from (0, 0); line to (100, 0); line to (100, 100); line to (0, 100); close }}\n\
             thickness = 1 mm\n\
             on = trough\n\
             {lines}\n\
         }}\n\
         let trough = nurbs_surface(degree: (1, 2), points: [row(-40 mm), row(140 mm)], \
         weights: [[1, cos(half), 1], [1, cos(half), 1]])\n"
    )
}

/// The distance of `p` from the trough's axis.
fn from_axis(p: DVec3) -> f64 {
    ((p.y - 50.0).powi(2) + (p.z - (10.0 - R)).powi(2)).sqrt()
}

/// The angle the plate spans about the axis: 50 mm either side of its top.
fn span() -> f64 {
    2.0 * (50.0 / R).asin()
}

/// Closed, manifold, consistently oriented and not through itself.
fn assert_sound(solid: &Mesh) {
    assert_closed_and_oriented(solid);
    assert!(
        crossings(solid).is_empty(),
        "the solid passes through itself"
    );
}

/// How far a tessellation of faces within `LAID_TOLERANCE` of the surface may put a
/// volume off: the tolerance times the solid's whole area.
fn volume_slack(solid: &Mesh) -> f64 {
    LAID_TOLERANCE * solid.total_area()
}

fn part(lines: &str) -> SheetPart {
    sheet_part(&trough_script(lines))
}

#[test]
fn a_plate_on_a_cylinder_has_the_cylinder_s_area_and_its_sides_lie_half_the_gauge_off_it() {
    let p = part("");
    assert_sound(&p.solid);
    let area = 100.0 * R * span();
    // Chords straying h from an arc of radius R are shorter than it by h / (3 R) of
    // its length: so much area at most, with room to spare.
    assert!(
        p.area < area && area - p.area < LAID_TOLERANCE * area / R,
        "area {} vs {area}",
        p.area
    );
    // Every corner of the top lies on the cylinder R + t/2, of the bottom on R - t/2.
    let solid = &p.solid;
    for (group, radius) in [("plate.top", R + 0.5), ("plate.bottom", R - 0.5)] {
        let g = solid.group(group).expect("the group");
        for t in g.faces() {
            for &i in solid.faces()[t.0 as usize].indices() {
                let r = from_axis(solid.positions()[i as usize]);
                assert!((r - radius).abs() < 1e-9, "{group}: {r} vs {radius}");
            }
        }
    }
    // The shell between R - t/2 and R + t/2 over the span: its volume is the area
    // times the thickness exactly.
    let exact = 100.0 * span() * R * 1.0;
    let v = volume(solid);
    assert!((v - exact).abs() < volume_slack(solid), "{v} vs {exact}");
    assert!((v - exact).abs() / exact < 1e-4, "{v} vs {exact}");
}

#[test]
fn a_flange_on_the_curved_edge_stands_along_the_normals_as_an_annulus() {
    let p = part("flange end = { at: (0, 50), height: 20 mm }");
    assert_sound(&p.solid);
    // The flange is the annulus between R and R + 20 in the plane x = 0.
    let flange = p
        .sheets
        .iter()
        .find(|s| s.name == "end")
        .expect("the flange");
    let exact = span() * ((R + 20.0).powi(2) - R * R) / 2.0;
    // Its arcs are followed by chords within the tolerance: each cuts off (or adds)
    // less than the tolerance times the arc's length.
    assert!(
        (exact - flange.area).abs() < LAID_TOLERANCE * (2.0 * R + 20.0) * span(),
        "{} vs {exact}",
        flange.area
    );
    // Its sides lie in the planes x = -t/2 and x = t/2 (outside, inside).
    let solid = &p.solid;
    for (group, x) in [("end.outside", -0.5), ("end.inside", 0.5)] {
        let g = solid.group(group).expect("the group");
        for t in g.faces() {
            for &i in solid.faces()[t.0 as usize].indices() {
                let q = solid.positions()[i as usize];
                assert!((q.x - x).abs() < 1e-9, "{group}: x = {}", q.x);
            }
        }
    }
    // The solid's cross-section about the axis is an L: the plate's band from x = -t/2
    // to 100 between R -+ t/2, and the flange's from R + t/2 to R + 20 between
    // x = -+ t/2, swept through the span (Pappus).
    let t = 1.0;
    let exact = span()
        * ((100.0 + t / 2.0) * R * t + t * ((R + 20.0).powi(2) - (R + t / 2.0).powi(2)) / 2.0);
    let v = volume(solid);
    assert!((v - exact).abs() < volume_slack(solid), "{v} vs {exact}");
}

#[test]
fn holes_lifts_and_flanges_on_part_of_an_edge_make_a_sound_solid() {
    let p = part(
        "flange side = { from: (20, 0), to: (90, 0), height: 15 mm, angle: 60 deg }\n\
         punch hole = sketch(top) { from (60, 40); arc to (80, 40) through (70, 50); arc to (60, 40) through (70, 30); close }\n\
         lift pad = { region: sketch(top) { from (20, 60); line to (50, 60); line to (50, 85); line to (20, 85); close }, height: 3 mm, draft: 20 deg }",
    );
    assert_sound(&p.solid);
    // Each sheet's area times its thickness, within the laid tolerance (the corners
    // of a curved mitre hold a little more or less than flat ones).
    let summed: f64 = p.sheets.iter().map(|s| s.area * s.thickness).sum();
    let v = volume(&p.solid);
    assert!(
        (v - summed).abs() < volume_slack(&p.solid),
        "{v} vs {summed}"
    );
    // The lifted top is the surface offset by 3 mm: its mid points lie at R + 3 from
    // the axis, so its solid corners at R + 3 +- t/2; exactly inside, and where it
    // meets its walls on the mitre of their tangent planes, within the curvature
    // times the thickness squared.
    let g = p.solid.group("pad.top").expect("the lifted top");
    for t in g.faces() {
        for &i in p.solid.faces()[t.0 as usize].indices() {
            let q = p.solid.positions()[i as usize];
            let r = from_axis(q);
            let off = (r - (R + 3.5)).abs().min((r - (R + 2.5)).abs());
            assert!(off < 1.0 / R, "pad.top: {r}");
            let inside = q.x > 21.0 && q.x < 49.0 && q.y > 61.0 && q.y < 84.0;
            assert!(!inside || off < 1e-9, "pad.top inside: {r}");
        }
    }
}

#[test]
fn a_doubly_curved_panel_s_sides_lie_half_the_gauge_off_it_by_closest_points() {
    // A saddle-free dome: a bicubic net over 200 x 160 mm rising 25 mm in the middle.
    let text = "units mm deg\n\
        let net = [[(i * 50 mm - 50 mm, j * 45 mm - 45 mm, 25 mm * sin(i * 45 deg) * sin(j * 45 deg) * sin(i * 45 deg) * sin(j * 45 deg)) for j in range(0, 5)] for i in range(0, 5)]\n\
        sheet inner {\n\
            outline = sketch(top) { from (0, 0); line to (100, 0); line to (100, 90); line to (0, 90); close }\n\
            thickness = 1.2 mm\n\
            on = dome\n\
            flange lip = { at: (100, 45), height: 12 mm }\n\
        }\n\
        let dome = nurbs_surface(degree: (3, 3), points: net)\n";
    let p = sheet_part(text);
    assert_sound(&p.solid);
    let Some(surface) = base_surface(text) else {
        panic!("the dome")
    };
    // Half the gauge off the dome: exactly away from the lip; on the mitre with the
    // lip (x near 100) within the curvature times the thickness squared, where the
    // two sides' offset tangent planes meet rather than the offset surfaces.
    for group in ["plate.top", "plate.bottom"] {
        let g = p.solid.group(group).expect("the group");
        for t in g.faces() {
            for &i in p.solid.faces()[t.0 as usize].indices() {
                let q = p.solid.positions()[i as usize];
                let foot = closest_point_on_surface(&surface, q).expect("a foot");
                let off = (foot.point.distance(q) - 0.6).abs();
                let bound = if q.x < 99.0 { 1e-7 } else { 1.2 * 1.2 / 100.0 };
                assert!(off < bound, "{group}: {off} mm off half the gauge at {q}");
            }
        }
    }
    let summed: f64 = p.sheets.iter().map(|s| s.area * s.thickness).sum();
    let v = volume(&p.solid);
    assert!(
        (v - summed).abs() < volume_slack(&p.solid),
        "{v} vs {summed}"
    );
}

/// The surface `dome` a script declares.
fn base_surface(text: &str) -> Option<dieface::geom::NurbsSurface> {
    script::evaluate_clean("part.die", text)
        .into_iter()
        .find_map(|(name, data)| match (name.as_str(), data) {
            ("dome", dieface::eval::Data::Surface(s)) => Some((*s).clone()),
            _ => None,
        })
}

#[test]
fn a_part_reaching_past_the_surface_or_on_a_wall_is_refused_at_on() {
    let past = trough_script("flange end = { at: (0, 50), height: 20 mm, angle: 30 deg }")
        .replace("row(-40 mm)", "row(-2 mm)");
    let found = diagnostics_of("part.die", &past);
    assert!(
        found
            .iter()
            .any(|d| d.message.contains("cannot be laid on its surface")
                && d.message.contains("does not reach under")),
        "{found:#?}"
    );
    let wall = "units mm deg\n\
        sheet panel {\n\
            outline = sketch(top) { from (0, 0); line to (10, 0); line to (10, 10); line to (0, 10); close }\n\
            thickness = 1 mm\n\
            on = nurbs_surface(degree: (1, 1), points: [[(-5, -5, 0), (-5, 15, 0)], [(15, -5, 300), (15, 15, 300)]])\n\
        }\n";
    let found = diagnostics_of("part.die", wall);
    assert!(
        found
            .iter()
            .any(|d| d.message.contains("steeper than 75 deg")),
        "{found:#?}"
    );
    let not_a_surface = trough_script("").replace("on = trough", "on = 3 mm");
    let found = diagnostics_of("part.die", &not_a_surface);
    assert!(
        found.iter().any(|d| d.message.contains("`on`")),
        "{found:#?}"
    );
}

#[test]
fn a_laid_part_is_the_same_bytes_each_time() {
    let a = part("flange end = { at: (0, 50), height: 20 mm }");
    let b = part("flange end = { at: (0, 50), height: 20 mm }");
    assert_eq!(a.solid.positions(), b.solid.positions());
    assert_eq!(a.solid.faces(), b.solid.faces());
}
