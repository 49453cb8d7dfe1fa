//! The `fill` block (issue 17) run the way a designer runs it: `dieface build` of
//! `examples/inner_panel` (an inner panel's FE mesh read from OBJ, 14 holes and a
//! 0.02 mm crack between two CAD patches). The glTF has the filled mesh's node of kind
//! `fill` with each fill patch and its base surface as children; the filled mesh read
//! back from the OBJ is manifold, wound alike, and has one free loop left (the panel's
//! outer edge); the fills lie on the panel's analytic surface; two builds give the same
//! bytes.

mod common;
#[path = "common/panel.rs"]
mod panel;

use std::path::Path;

use dieface::geom::mesh::{Face, Mesh, Topology};

#[test]
fn the_inner_panel_is_stitched_and_filled_by_the_real_binary() {
    let dir = common::fresh_dir("mesh_fill_language", "inner_panel");
    let example = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/inner_panel");
    for file in ["inner_panel.die", "inner_panel.obj"] {
        std::fs::copy(example.join(file), dir.join(file)).expect("copy the example");
    }
    let (code, _, stderr) = common::run_dieface(
        &dir,
        &["build", "inner_panel.die", "-o", "a.gltf", "-o", "a.obj"],
    );
    assert_eq!(code, Some(0), "{stderr}");
    let gltf: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("a.gltf")).expect("gltf"))
            .expect("JSON");
    let nodes = gltf["nodes"].as_array().expect("nodes");
    let node = |name: &str| {
        nodes
            .iter()
            .find(|n| n["name"] == name)
            .unwrap_or_else(|| panic!("no node {name}"))
    };
    assert_eq!(node("closed")["extras"]["kind"], "fill");
    assert_eq!(node("closed/mesh")["extras"]["kind"], "fill");
    for k in 1..=14 {
        assert_eq!(
            node(&format!("closed/patch_{k}"))["extras"]["kind"],
            "fill_patch"
        );
        assert_eq!(
            node(&format!("closed/base_{k}"))["extras"]["kind"],
            "fill_base"
        );
    }
    assert_eq!(
        node("closed")["children"].as_array().map(Vec::len),
        Some(1 + 2 * 14),
        "the mesh, and a patch and a base surface per hole"
    );

    // The filled mesh as the OBJ gives it (welded at the OBJ's precision).
    let (positions, faces) = common::obj_object(&dir.join("a.obj"), "closed/mesh");
    let faces: Vec<Face> = faces
        .iter()
        .map(|&[a, b, c]| Face::triangle(a, b, c))
        .collect();
    let mesh = Mesh::new(positions, faces)
        .expect("a mesh")
        .weld(1e-7)
        .expect("welded");
    let topology = Topology::build(&mesh);
    assert!(topology.non_manifold_edges().is_empty());
    assert!(topology.inconsistent_edges().is_empty());
    let loops = topology.boundary_loops();
    assert_eq!(loops.loops.len(), 1, "only the outer edge is left free");
    assert!(loops.open_chains.is_empty());
    // The outer edge is the panel's rectangle: every node on it lies on a side.
    let on_side = loops.loops[0].vertices.iter().all(|v| {
        let p = mesh.positions()[v.index()];
        let near = |a: f64, b: f64| (a - b).abs() < 0.05;
        near(p.x, 0.0) || near(p.x, panel::WIDTH) || near(p.y, 0.0) || near(p.y, panel::DEPTH)
    });
    assert!(on_side, "the loop left is the panel's outer edge");

    // Each patch's nodes on the panel's surface: within 0.05 mm where the surface is
    // gentle, and the 12 mm mesh's own chord sag (0.5 mm) on the ridge.
    let mut worst_gentle = 0.0f64;
    let mut worst = 0.0f64;
    for k in 1..=14 {
        let (points, _) = common::obj_object(&dir.join("a.obj"), &format!("closed/patch_{k}"));
        for p in points {
            let off = panel::distance_to_surface(p);
            worst = worst.max(off);
            if panel::smallest_radius(p.x, p.y) >= 500.0 {
                worst_gentle = worst_gentle.max(off);
            }
        }
    }
    eprintln!("fill nodes off the surface: {worst_gentle:.4} mm where R >= 500 mm, {worst:.4} mm at the most");
    assert!(worst_gentle < 0.05, "{worst_gentle}");
    assert!(worst < 0.5, "{worst}");

    let again = common::run_dieface(&dir, &["build", "inner_panel.die", "-o", "b.gltf"]);
    assert_eq!(again.0, Some(0));
    assert_eq!(
        std::fs::read(dir.join("a.gltf")).expect("a"),
        std::fs::read(dir.join("b.gltf")).expect("b"),
        "the same script gives the same bytes"
    );
}
