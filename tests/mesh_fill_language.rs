//! The `fill` block (issue 17) run the way a designer runs it: `dieface build` of
//! `examples/inner_panel` (an inner panel's FE mesh read from OBJ, 14 holes and a
//! 0.02 mm crack between two CAD patches). The glTF has the filled mesh's node of kind
//! `fill` with each fill patch and its base surface as children; the filled mesh read
//! back from the OBJ is manifold, wound alike, and has one free loop left (the panel's
//! outer edge); the fills lie on the panel's analytic surface; two builds give the same
//! bytes. A panel exported with a group per CAD patch and a normal per facet reads as
//! the one piece it is.

mod common;
#[path = "common/panel.rs"]
mod panel;

use std::path::Path;

use dieface::geom::mesh::{Face, FaceId, Mesh, Topology};

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

/// `dieface inspect --json panel.die` in `dir`: each declaration's value by name.
fn inspected(dir: &Path) -> impl Fn(&str) -> serde_json::Value {
    let (code, stdout, stderr) = common::run_dieface(dir, &["inspect", "--json", "panel.die"]);
    assert_eq!(code, Some(0), "{stderr}");
    let json: serde_json::Value = serde_json::from_str(&stdout).expect("JSON");
    move |name: &str| {
        json["declarations"]
            .as_array()
            .and_then(|d| d.iter().find(|d| d["name"] == name))
            .map(|d| d["value"].clone())
            .unwrap_or_else(|| panic!("no {name}"))
    }
}

/// The panel as an FE pre-processor exports it: a group per CAD patch (left and right
/// halves, sharing the nodes on the line between them) and a normal per facet
/// (`f a//k b//k c//k`).
fn panel_obj_with_patches_and_facet_normals(mesh: &Mesh) -> String {
    let mut text = String::new();
    for p in mesh.positions() {
        text.push_str(&format!("v {} {} {}\n", p.x, p.y, p.z));
    }
    for k in 0..mesh.face_count() {
        let n = mesh.face_normal(FaceId(k as u32)).unwrap_or(glam::DVec3::Z);
        text.push_str(&format!("vn {} {} {}\n", n.x, n.y, n.z));
    }
    let left = |f: &Face| mesh.positions()[f.indices()[0] as usize].x < panel::WIDTH / 2.0;
    for (name, side) in [("patch_left", true), ("patch_right", false)] {
        text.push_str(&format!("g {name}\n"));
        for (k, f) in mesh.faces().iter().enumerate() {
            if left(f) == side {
                let [a, b, c] = [0, 1, 2].map(|i| f.indices()[i] + 1);
                let n = k + 1;
                text.push_str(&format!("f {a}//{n} {b}//{n} {c}//{n}\n"));
            }
        }
    }
    text
}

#[test]
fn a_panel_exported_in_patches_with_facet_normals_reads_as_one_piece_and_fills() {
    let dir = common::fresh_dir("mesh_fill_language", "patches");
    let holes = panel::standard_holes();
    let mesh = panel::panel(12.0, &holes);
    std::fs::write(
        dir.join("panel.obj"),
        panel_obj_with_patches_and_facet_normals(&mesh),
    )
    .expect("the OBJ written");
    std::fs::write(
        dir.join("panel.die"),
        "let panel = read_obj(\"panel.obj\")\nlet free = free_edges(panel)\nfill closed { mesh = panel }\nlet left = free_edges(closed.mesh)\n",
    )
    .expect("the script written");
    let value = inspected(&dir);
    let read = value("panel");
    assert_eq!(
        read["vertices"],
        mesh.vertex_count(),
        "one node per `v` line"
    );
    let groups: Vec<&str> = read["groups"]
        .as_array()
        .expect("groups")
        .iter()
        .filter_map(|g| g["name"].as_str())
        .collect();
    assert_eq!(groups, ["patch_left", "patch_right"]);
    let number = |v: &serde_json::Value, field: &str| v["fields"][field]["value"].as_f64();
    let free = value("free");
    assert_eq!(
        number(&free, "pieces"),
        Some(1.0),
        "the patches share their nodes"
    );
    assert_eq!(
        free["fields"]["loops"].as_array().map(Vec::len),
        Some(holes.len() + 1),
        "the holes and the outer edge, no seam between the patches"
    );
    let left = value("left");
    assert_eq!(left["fields"]["loops"].as_array().map(Vec::len), Some(1));
}

/// A quad-meshed panel, 200 x 100 mm at 5 mm on a gentle dome, a 40 mm hole cut out at
/// (100, 50) and a 0.02 mm crack at x = 150 between two patches, node for node: OBJ text.
fn quad_panel_obj() -> (String, usize) {
    let (columns, rows, h) = (41usize, 21usize, 5.0f64);
    let z = |x: f64, y: f64| 0.0005 * (x - 100.0).powi(2) + 0.001 * (y - 50.0).powi(2);
    let mut text = String::new();
    // The nodes row by row; the seam's column twice, the right patch's copy 0.02 mm on.
    let mut id = vec![[0usize; 2]; columns * rows];
    let mut count = 0;
    for j in 0..rows {
        for i in 0..columns {
            let (x, y) = (i as f64 * h, j as f64 * h);
            count += 1;
            id[j * columns + i] = [count, count];
            text.push_str(&format!("v {x} {y} {}\n", z(x, y)));
            if i == 30 {
                count += 1;
                id[j * columns + i][1] = count;
                text.push_str(&format!("v {} {y} {}\n", x + 0.02, z(x + 0.02, y)));
            }
        }
    }
    let mut quads = 0;
    for (name, right) in [("left", false), ("right", true)] {
        text.push_str(&format!("g {name}\n"));
        for j in 0..rows - 1 {
            for i in 0..columns - 1 {
                let (cx, cy) = ((i as f64 + 0.5) * h, (j as f64 + 0.5) * h);
                if (i >= 30) != right || (cx - 100.0).hypot(cy - 50.0) < 20.0 {
                    continue;
                }
                let side = usize::from(right);
                let n = |a: usize, b: usize| id[b * columns + a][side];
                let corners = [n(i, j), n(i + 1, j), n(i + 1, j + 1), n(i, j + 1)];
                text.push_str(&format!(
                    "f {} {} {} {}\n",
                    corners[0], corners[1], corners[2], corners[3]
                ));
                quads += 1;
            }
        }
    }
    (text, quads)
}

#[test]
fn a_quad_mesh_keeps_its_quads_when_its_crack_is_stitched_and_its_hole_filled() {
    let dir = common::fresh_dir("mesh_fill_language", "quads");
    let (obj, quads) = quad_panel_obj();
    std::fs::write(dir.join("panel.obj"), obj).expect("the OBJ written");
    std::fs::write(
        dir.join("panel.die"),
        "let panel = read_obj(\"panel.obj\")\nfill closed {\n    mesh = panel\n    stitch = 0.05 mm\n}\nlet filled = closed.mesh\nlet left = free_edges(filled)\n",
    )
    .expect("the script written");
    let value = inspected(&dir);
    let filled = value("filled");
    assert_eq!(
        filled["quads"], quads,
        "every quad kept as it was: {filled}"
    );
    assert!(
        filled["triangles"].as_u64().is_some_and(|t| t > 0),
        "the fill's triangles"
    );
    let left = value("left");
    assert_eq!(
        left["fields"]["loops"].as_array().map(Vec::len),
        Some(1),
        "the crack closed and the hole filled: the outer edge alone is left"
    );
}
