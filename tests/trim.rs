//! `trim(surface, outline)`: the product trimmed at its outline, through the language,
//! the step draw and the export.

use std::path::Path;

use dieface::eval::{Data, Engine};
use dieface::export::{build_scene, Geometry};
use dieface::geom::inversion::closest_point_on_curve;
use dieface::geom::tessellate::Tolerance;

#[path = "common/script.rs"]
mod script;

const PANEL: &str = r#"
import "std/sketch" as sk
let panel = nurbs_surface(degree: (3, 2), points: [
    [(-300, -250, 0), (-300, 0, 10), (-300, 250, 0)],
    [(-100, -250, 5), (-100, 0, 25), (-100, 250, 5)],
    [(100, -250, 5), (100, 0, 25), (100, 250, 5)],
    [(300, -250, 0), (300, 0, 10), (300, 250, 0)]])
let outline = project(sk.rectangle(top, (0, 0), 400 mm, 300 mm, 50 mm), panel)
product part = trim(panel, outline)
"#;

#[test]
fn trim_makes_a_trimmed_surface_with_the_outline_as_its_loop() {
    let values = script::evaluate_clean("trim.die", PANEL);
    let get = |n: &str| values.iter().find(|(k, _)| k == n).map(|(_, d)| d).unwrap();
    let (Data::Trimmed(t), Data::Curve3(outline)) = (get("part"), get("outline")) else {
        panic!("part must be a trimmed surface and outline a curve");
    };
    assert_eq!(t.outer().curve(), &**outline);
    let Data::Surface(panel) = get("panel") else {
        panic!("panel is a surface")
    };
    assert_eq!(t.surface(), &**panel);
    // Smaller than the panel, larger than the flat rectangle under it.
    let flat = 400.0 * 300.0 - (4.0 - std::f64::consts::PI) * 50.0 * 50.0;
    assert!(
        t.area() > flat && t.area() < panel.area(),
        "area {}",
        t.area()
    );
}

#[test]
fn the_export_carries_the_product_cut_at_the_outline_and_not_the_panel() {
    let mut engine = Engine::new(None);
    let outcome = engine.evaluate("trim.die", PANEL, None);
    let values = script::clean_values(&engine, &outcome);
    let Some(Data::Curve3(outline)) = values
        .iter()
        .find(|(n, _)| n == "outline")
        .map(|(_, v)| &v.data)
    else {
        panic!("outline is a curve")
    };
    let tol = Tolerance::new(0.05).unwrap();
    let scene = build_scene(&engine.die_model(&outcome), &tol).unwrap();
    assert!(
        scene.find("panel").is_none(),
        "the trimmed panel is not exported again"
    );
    let part = scene.find("part").expect("the product is exported");
    assert_eq!(part.kind, "product");
    let Geometry::Triangles {
        positions, indices, ..
    } = &*part.geometry[0]
    else {
        panic!("the product is triangles")
    };
    let mesh = dieface::geom::mesh::Mesh::new(
        positions.clone(),
        indices
            .chunks(3)
            .map(|t| dieface::geom::mesh::Face::triangle(t[0], t[1], t[2]))
            .collect(),
    )
    .unwrap();
    let loops = mesh.topology().boundary_loops();
    assert_eq!(loops.loops.len(), 1);
    for &v in &loops.loops[0].vertices {
        let d = closest_point_on_curve(outline, mesh.position(v).unwrap())
            .unwrap()
            .distance;
        assert!(d < 1e-9, "a boundary vertex is {d} mm off the outline");
    }
    // Nothing of the mesh lies outside the outline, seen from the top (the projected
    // outline itself is fitted within 1e-4 mm).
    let max_x = positions.iter().map(|p| p.x.abs()).fold(0.0, f64::max);
    let max_y = positions.iter().map(|p| p.y.abs()).fold(0.0, f64::max);
    assert!(
        max_x <= 200.0 + 2e-4 && max_y <= 150.0 + 2e-4,
        "{max_x} {max_y}"
    );
}

#[test]
fn the_step_draw_takes_the_trimmed_product() {
    // The fender example gives its step draw the trimmed product: its outline is the
    // step draw's product guide, and its surface the slope the sections start along.
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/fender");
    let text = std::fs::read_to_string(root.join("fender.die")).unwrap();
    let with_curve = text.replace("    product = fender\n", "    product = outline\n");
    assert_ne!(
        text, with_curve,
        "the example gives the step draw `product = fender`"
    );
    let area = |src: &str| {
        let mut engine = Engine::new(None);
        let outcome = engine.evaluate("fender.die", src, None);
        let values = script::clean_values(&engine, &outcome);
        let (_, v) = values.iter().find(|(n, _)| n == "addendum").unwrap();
        let Data::Record(r) = &v.data else { panic!() };
        r.fields
            .iter()
            .filter_map(|(_, v)| match &v.data {
                Data::Surface(s) => Some(s.area()),
                _ => None,
            })
            .sum::<f64>()
    };
    // With the product's slope not used, the trimmed product gives the step draw the
    // outline curve gives; with it (the default), the sections start tangentially,
    // which moves the step draw.
    let drawn_start = text.replace(
        "    product = fender\n",
        "    product = fender\n    tangent_product = false\n",
    );
    let (a, b, tangent) = (area(&drawn_start), area(&with_curve), area(&text));
    assert!(a > 0.0 && a == b, "{a} vs {b}");
    assert!(tangent != a, "the tangent start changed nothing: {tangent}");
}
