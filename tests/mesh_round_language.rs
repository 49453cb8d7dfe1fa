//! The `round` block (issue 16): a mesh's sharp edge rounded from a script, the way a
//! designer runs it. The fold of `tests/diagnostics/support/fold.obj` (two 40 mm legs at
//! 90 deg, 100 mm long) rounded at R 5 mm with `dieface build`: the glTF has the round's
//! node of kind `round` with the rounded mesh, the rounding surface and the two trim
//! lines as its children; the rounded mesh read back from the OBJ is sound and its
//! round lies on the fillet; two builds give the same bytes.

mod common;

use std::path::Path;

use dieface::geom::mesh::Topology;

const SCRIPT: &str = r#"units mm deg
let die = read_obj("fold.obj")
round shoulder {
    mesh = die
    at = (50, 0, 0)
    radius = 5 mm
}
"#;

#[test]
fn a_fold_rounded_from_a_script_exports_its_round() {
    let dir = common::fresh_dir("mesh_round_language", "fold");
    let support = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/diagnostics/support/fold.obj");
    std::fs::copy(support, dir.join("fold.obj")).expect("copy the mesh");
    std::fs::write(dir.join("part.die"), SCRIPT).expect("write the script");
    let (code, _, stderr) =
        common::run_dieface(&dir, &["build", "part.die", "-o", "a.gltf", "-o", "a.obj"]);
    assert_eq!(code, Some(0), "{stderr}");
    let gltf: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("a.gltf")).expect("gltf"))
            .expect("JSON");
    let nodes = gltf["nodes"].as_array().expect("nodes");
    let kind = |name: &str| {
        nodes
            .iter()
            .find(|n| n["name"] == name)
            .map(|n| n["extras"]["kind"].clone())
            .unwrap_or_else(|| panic!("no node {name}"))
    };
    assert_eq!(kind("shoulder"), "round");
    assert_eq!(kind("shoulder/mesh"), "round");
    assert_eq!(kind("shoulder/surface"), "round_surface");
    assert_eq!(kind("shoulder/trim_left"), "trim_line");
    assert_eq!(kind("shoulder/trim_right"), "trim_line");
    let round = nodes
        .iter()
        .find(|n| n["name"] == "shoulder")
        .expect("round");
    assert_eq!(round["children"].as_array().map(Vec::len), Some(4));
    // The rounded mesh as the OBJ gives it: sound, and its nodes off the legs on the
    // fillet's cylinder (axis (x, -5, 5), radius 5) to the OBJ's 1e-6 mm.
    let (positions, faces) = common::obj_object(&dir.join("a.obj"), "shoulder/mesh");
    let mesh = dieface::geom::mesh::Mesh::new(
        positions,
        faces
            .iter()
            .map(|&[a, b, c]| dieface::geom::mesh::Face::triangle(a, b, c))
            .collect(),
    )
    .expect("a mesh")
    .weld(1e-7)
    .expect("welded");
    let topology = Topology::build(&mesh);
    assert!(topology.non_manifold_edges().is_empty());
    assert!(topology.inconsistent_edges().is_empty());
    assert_eq!(topology.boundary_loops().loops.len(), 1);
    let on_fillet = mesh
        .positions()
        .iter()
        .filter(|p| p.y < -1e-6 && p.z > 1e-6)
        .map(|p| (((p.y + 5.0).powi(2) + (p.z - 5.0).powi(2)).sqrt() - 5.0).abs())
        .fold(0.0, f64::max);
    assert!(on_fillet < 1e-5, "{on_fillet}");
    let again = common::run_dieface(&dir, &["build", "part.die", "-o", "b.gltf"]);
    assert_eq!(again.0, Some(0));
    assert_eq!(
        std::fs::read(dir.join("a.gltf")).expect("a"),
        std::fs::read(dir.join("b.gltf")).expect("b"),
        "the same script gives the same bytes"
    );
}
