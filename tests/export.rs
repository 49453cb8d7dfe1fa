//! Export: scenes from scripts, glTF and OBJ encoding, determinism, atomic writes.
//! (The Khronos validator run is `tests/gltf_validator.rs`.)

mod common;

use std::path::{Path, PathBuf};

use dieface::eval::Engine;
use dieface::export::atomic::write_atomic;
use dieface::export::{build_scene, encode, Format, Geometry, Node, Scene};
use dieface::geom::tessellate::Tolerance;
use glam::DVec3;
use serde_json::Value as Json;

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn examples() -> Vec<PathBuf> {
    common::die_files("examples")
}

fn tol() -> Tolerance {
    Tolerance::new(0.01).expect("valid tolerance")
}

/// A fresh engine's scene of an example file.
fn scene_of_path(script: &Path) -> Scene {
    let mut engine = Engine::new(Some(root().join("examples")));
    let outcome = engine.evaluate_path(script).expect("readable example");
    assert!(outcome.diagnostics.is_empty(), "{}", script.display());
    build_scene(&engine.die_model(&outcome), &tol()).expect("tessellates")
}

/// The scene of a script given as text.
fn scene_of(src: &str) -> Scene {
    let mut engine = Engine::new(None);
    let outcome = engine.evaluate("test.die", src, None);
    assert!(
        outcome.diagnostics.is_empty(),
        "{:?}",
        outcome
            .diagnostics
            .iter()
            .map(|d| engine.sources.render(d, false))
            .collect::<Vec<_>>()
    );
    build_scene(&engine.die_model(&outcome), &tol()).expect("tessellates")
}

/// A parsed GLB: its JSON and its BIN chunk, with the container checked on the way.
fn parse_glb(bytes: &[u8]) -> (Json, Vec<u8>) {
    let word = |at: usize| u32::from_le_bytes(bytes[at..at + 4].try_into().unwrap());
    assert_eq!(&bytes[0..4], b"glTF");
    assert_eq!(word(4), 2, "GLB version");
    assert_eq!(word(8) as usize, bytes.len(), "GLB length field");
    let json_len = word(12) as usize;
    assert_eq!(&bytes[16..20], b"JSON");
    assert_eq!(json_len % 4, 0, "JSON chunk padded to 4 bytes");
    let json_bytes = &bytes[20..20 + json_len];
    let trimmed = json_bytes.iter().rposition(|&b| b != b' ').unwrap() + 1;
    assert!(json_len - trimmed < 4, "JSON padded with spaces only");
    let json: Json = serde_json::from_slice(json_bytes).expect("JSON chunk parses");
    let mut bin = Vec::new();
    let at = 20 + json_len;
    if at < bytes.len() {
        let bin_len = word(at) as usize;
        assert_eq!(&bytes[at + 4..at + 8], b"BIN\0");
        assert_eq!(bin_len % 4, 0, "BIN chunk padded to 4 bytes");
        assert_eq!(at + 8 + bin_len, bytes.len());
        bin = bytes[at + 8..].to_vec();
    }
    (json, bin)
}

/// The `f32` VEC3 elements of accessor `a`.
fn vec3s(json: &Json, bin: &[u8], a: u64) -> Vec<[f32; 3]> {
    let acc = &json["accessors"][a as usize];
    assert_eq!(acc["componentType"], 5126);
    assert_eq!(acc["type"], "VEC3");
    let view = &json["bufferViews"][acc["bufferView"].as_u64().unwrap() as usize];
    let offset = view["byteOffset"].as_u64().unwrap() as usize;
    assert_eq!(offset % 4, 0, "buffer views start on 4-byte boundaries");
    let count = acc["count"].as_u64().unwrap() as usize;
    (0..count)
        .map(|i| {
            let f = |k: usize| {
                let at = offset + 12 * i + 4 * k;
                f32::from_le_bytes(bin[at..at + 4].try_into().unwrap())
            };
            [f(0), f(1), f(2)]
        })
        .collect()
}

fn node_named<'a>(json: &'a Json, name: &str) -> &'a Json {
    json["nodes"]
        .as_array()
        .unwrap()
        .iter()
        .find(|n| n["name"] == name)
        .unwrap_or_else(|| panic!("no node {name} in {}", json["nodes"]))
}

fn close(a: [f32; 3], b: [f64; 3]) -> bool {
    a.iter()
        .zip(b)
        .all(|(&x, y)| (f64::from(x) - y).abs() < 1e-6)
}

#[test]
fn format_comes_from_the_extension() {
    assert_eq!(
        Format::from_path(Path::new("a/fender.glb")),
        Some(Format::Glb)
    );
    assert_eq!(
        Format::from_path(Path::new("fender.GLTF")),
        Some(Format::Gltf)
    );
    assert_eq!(
        Format::from_path(Path::new("fender.obj")),
        Some(Format::Obj)
    );
    assert_eq!(Format::from_path(Path::new("fender.stl")), None);
    assert_eq!(Format::from_path(Path::new("fender")), None);
}

#[test]
fn every_example_builds_to_identical_bytes_twice() {
    let scripts = examples();
    assert!(scripts.len() >= 3, "examples: {scripts:?}");
    for script in scripts {
        let (a, b) = (scene_of_path(&script), scene_of_path(&script));
        assert!(!a.nodes.is_empty(), "{} exports nothing", script.display());
        for format in [Format::Glb, Format::Gltf, Format::Obj] {
            let (x, y) = (encode(&a, format), encode(&b, format));
            assert!(!x.is_empty());
            assert!(
                x == y,
                "{} as {format:?}: two builds differ",
                script.display()
            );
        }
    }
}

#[test]
fn press_millimetres_become_gltf_metres_with_y_up() {
    // A straight curve: its two ends are its polyline.
    let scene = scene_of("let c = line_between((10, 20, 30), (40, -50, 60))");
    let (json, bin) = parse_glb(&encode(&scene, Format::Glb));
    let mesh = node_named(&json, "c")["mesh"].as_u64().unwrap() as usize;
    let prim = &json["meshes"][mesh]["primitives"][0];
    assert_eq!(prim["mode"], 3, "a curve is a LINE_STRIP");
    let pos = prim["attributes"]["POSITION"].as_u64().unwrap();
    let points = vec3s(&json, &bin, pos);
    assert_eq!(points.len(), 2);
    // (x, y, z) mm -> (x, z, -y) m
    assert!(close(points[0], [0.010, 0.030, -0.020]), "{points:?}");
    assert!(close(points[1], [0.040, 0.060, 0.050]), "{points:?}");
    let acc = &json["accessors"][pos as usize];
    let min: Vec<f64> = serde_json::from_value(acc["min"].clone()).unwrap();
    let max: Vec<f64> = serde_json::from_value(acc["max"].clone()).unwrap();
    for k in 0..3 {
        let lo = points[0][k].min(points[1][k]);
        let hi = points[0][k].max(points[1][k]);
        assert_eq!(min[k], f64::from(lo), "min is exact on the f32 data");
        assert_eq!(max[k], f64::from(hi), "max is exact on the f32 data");
    }
}

#[test]
fn normals_turn_with_the_axes() {
    // A flat square at z = 5 mm: press normal +-Z, glTF normal +-Y.
    let scene = scene_of(
        "product p = nurbs_surface(degree: (1, 1), points: [[(0, 0, 5), (0, 100, 5)], [(100, 0, 5), (100, 100, 5)]])",
    );
    let Geometry::Triangles { normals, .. } = &*scene.nodes[0].geometry[0] else {
        panic!("a surface gives triangles");
    };
    let press = normals[0];
    assert!((press.z.abs() - 1.0).abs() < 1e-9, "{press}");
    let (json, bin) = parse_glb(&encode(&scene, Format::Glb));
    let prim = &json["meshes"][0]["primitives"][0];
    assert_eq!(prim["mode"], 4);
    let n = vec3s(&json, &bin, prim["attributes"]["NORMAL"].as_u64().unwrap());
    let p = vec3s(
        &json,
        &bin,
        prim["attributes"]["POSITION"].as_u64().unwrap(),
    );
    assert_eq!(n.len(), p.len());
    for v in &n {
        assert!(close(*v, [0.0, press.z, 0.0]), "{v:?}");
    }
    for v in &p {
        assert!(
            (v[1] - 0.005).abs() < 1e-7,
            "height 5 mm is glTF y = 0.005 m: {v:?}"
        );
    }
}

const FEATURE: &str = r#"
let flange = nurbs_surface(degree: (1, 1), points: [[(0, 0, 0), (0, 100, 0)], [(100, 0, 0), (100, 100, 0)]])

let pol = {
    top: sketch(top) { from (0, 0); line to (100, 0); line to (100, 50); close },
    side_front: line_between((0, 0, 0), (100, 0, 0)),
    depth: 40 mm,
    corners: {
        patch: flange,
        radius: 5 mm,
    },
}

let beads = [
    sketch(top) { from (0, -40); line to (100, -40) },
    12 mm,
    sketch(top) { from (0, 140); line to (100, 140) },
]

let count = 3
product panel = flange
"#;

#[test]
fn nodes_are_named_nested_and_carry_extras() {
    let scene = scene_of(FEATURE);
    let top: Vec<&str> = scene.nodes.iter().map(|n| n.name.as_str()).collect();
    assert_eq!(
        top,
        ["flange", "pol", "beads", "panel"],
        "numbers are not exported"
    );
    let pol = scene.find("pol").unwrap();
    let parts: Vec<&str> = pol.children.iter().map(|n| n.name.as_str()).collect();
    assert_eq!(parts, ["pol/top", "pol/side_front", "pol/corners"]);
    let corners = &pol.children[2];
    assert_eq!(corners.children.len(), 1);
    assert_eq!(corners.children[0].name, "pol/corners/patch");
    assert!(pol.geometry.is_empty(), "a record is a group");
    let beads = scene.find("beads").unwrap();
    let parts: Vec<&str> = beads.children.iter().map(|n| n.name.as_str()).collect();
    assert_eq!(
        parts,
        ["beads/0", "beads/2"],
        "list children keep their index"
    );
    // Lines: the declaration's, or the part's own expression inside it.
    assert_eq!(pol.line, 4);
    assert_eq!(scene.find("pol/side_front").unwrap().line, 6);
    assert_eq!(scene.find("beads/2").unwrap().line, 17);
    for n in scene.all_nodes() {
        assert_eq!(n.kind, if n.name == "panel" { "product" } else { "let" });
    }

    let (json, _) = parse_glb(&encode(&scene, Format::Glb));
    assert_eq!(json["asset"]["version"], "2.0");
    assert_eq!(
        json["asset"]["generator"],
        format!("dieface {}", env!("CARGO_PKG_VERSION"))
    );
    let roots: Vec<&str> = json["scenes"][0]["nodes"]
        .as_array()
        .unwrap()
        .iter()
        .map(|i| {
            json["nodes"][i.as_u64().unwrap() as usize]["name"]
                .as_str()
                .unwrap()
        })
        .collect();
    assert_eq!(roots, ["flange", "pol", "beads", "panel"]);
    let pol = node_named(&json, "pol");
    let children: Vec<&str> = pol["children"]
        .as_array()
        .unwrap()
        .iter()
        .map(|i| {
            json["nodes"][i.as_u64().unwrap() as usize]["name"]
                .as_str()
                .unwrap()
        })
        .collect();
    assert_eq!(children, ["pol/top", "pol/side_front", "pol/corners"]);
    assert!(pol.get("mesh").is_none());
    let extras = &node_named(&json, "pol/side_front")["extras"];
    assert_eq!(extras["name"], "pol/side_front");
    assert_eq!(extras["kind"], "let");
    assert_eq!(extras["line"], 6);
    assert_eq!(extras["tolerance_mm"], 0.01);
    assert_eq!(extras["source"], "test.die");
    for n in json["nodes"].as_array().unwrap() {
        assert_eq!(n["extras"]["name"], n["name"], "every node has extras");
    }
}

#[test]
fn one_material_per_kind_with_distinct_colours() {
    let scene = scene_of(FEATURE);
    let (json, _) = parse_glb(&encode(&scene, Format::Glb));
    let materials = json["materials"].as_array().unwrap();
    let names: Vec<&str> = materials
        .iter()
        .map(|m| m["name"].as_str().unwrap())
        .collect();
    assert_eq!(names, ["let", "product"]);
    assert_ne!(
        materials[0]["pbrMetallicRoughness"]["baseColorFactor"],
        materials[1]["pbrMetallicRoughness"]["baseColorFactor"]
    );
    assert!(materials.iter().all(|m| m["doubleSided"] == true));
    let panel = node_named(&json, "panel")["mesh"].as_u64().unwrap() as usize;
    assert_eq!(json["meshes"][panel]["primitives"][0]["material"], 1);
    // The feature kinds to come get colours of their own.
    let kinds = [
        "product",
        "step_draw",
        "blankholder",
        "punch_opening",
        "bead",
        "let",
    ];
    // Every kind's colour as the fender's scene carries it (a `let` is plain grey).
    let fender = scene_of_path(&root().join("examples/fender/fender.die"));
    let all = fender.all_nodes();
    let colour = |kind: &str| -> [f64; 3] {
        match all.iter().find(|n| n.kind == kind) {
            Some(n) => n.color,
            None => dieface::die::model::PLAIN_COLOR,
        }
    };
    let colours: Vec<[f64; 3]> = kinds.iter().map(|k| colour(k)).collect();
    for i in 0..colours.len() {
        for j in i + 1..colours.len() {
            assert_ne!(colours[i], colours[j], "{} and {}", kinds[i], kinds[j]);
        }
    }
}

#[test]
fn sketches_are_line_strips() {
    let scene = scene_of_path(&root().join("examples/fender/fender.die"));
    let profile = scene
        .find("punch_profile")
        .expect("the punch profile is exported");
    let Geometry::LineStrip { points } = &*profile.geometry[0] else {
        panic!("a sketch is a line strip");
    };
    assert!(
        points.len() > 10,
        "fillets are tessellated: {}",
        points.len()
    );
    assert!(
        points.first().unwrap().distance(*points.last().unwrap()) < 1e-9,
        "closed"
    );
    assert!(points.iter().all(|p| p.z == 0.0), "top view at z = 0");
    let (json, _) = parse_glb(&encode(&scene, Format::Glb));
    let mesh = node_named(&json, "punch_profile")["mesh"].as_u64().unwrap() as usize;
    let prim = &json["meshes"][mesh]["primitives"][0];
    assert_eq!(prim["mode"], 3);
    assert!(
        prim.get("material").is_some(),
        "line strips have a material"
    );
    assert!(prim.get("indices").is_none());
    let fender = node_named(&json, "fender")["mesh"].as_u64().unwrap() as usize;
    assert_eq!(json["meshes"][fender]["primitives"][0]["mode"], 4);
}

#[test]
fn a_two_d_curve_lies_at_z_zero() {
    let scene = scene_of("let c = interpolate([(0, 0), (50, 20), (100, 0)], degree: 2)");
    let Geometry::LineStrip { points } = &*scene.nodes[0].geometry[0] else {
        panic!("a curve is a line strip");
    };
    assert!(points.len() > 2);
    assert!(points.iter().all(|p| p.z == 0.0));
}

#[test]
fn obj_has_groups_normals_faces_and_polylines() {
    let scene = scene_of(FEATURE);
    let text = String::from_utf8(encode(&scene, Format::Obj)).unwrap();
    assert!(text.starts_with("# dieface "));
    assert!(text.contains("millimetres"), "the header states the units");
    for name in [
        "flange",
        "pol/top",
        "pol/side_front",
        "pol/corners/patch",
        "beads/0",
        "beads/2",
        "panel",
    ] {
        assert!(
            text.contains(&format!("\no {name}\ng {name}\n")),
            "group {name}:\n{text}"
        );
    }
    assert!(
        !text.contains("\ng pol\n"),
        "a group node has no geometry of its own"
    );
    let count = |tag: &str| text.lines().filter(|l| l.starts_with(tag)).count();
    let vertices: usize = scene
        .all_nodes()
        .iter()
        .flat_map(|n| &n.geometry)
        .map(|g| match &**g {
            Geometry::Triangles { positions, .. } => positions.len(),
            Geometry::LineStrip { points } => points.len(),
        })
        .sum();
    assert_eq!(count("v "), vertices);
    assert!(count("vn ") > 0);
    assert_eq!(count("l "), 4, "pol/top, pol/side_front, beads/0, beads/2");
    // Faces point at valid vertices, with the same index for the normal.
    for l in text.lines().filter(|l| l.starts_with("f ")) {
        for corner in l[2..].split(' ') {
            let (v, n) = corner.split_once("//").expect("v//vn");
            assert_eq!(v, n);
            let v: usize = v.parse().unwrap();
            assert!(v >= 1 && v <= vertices);
        }
    }
    // The side-front polyline: millimetres, press coordinates.
    let at = text.find("\no pol/side_front\n").unwrap();
    let block: Vec<&str> = text[at..]
        .lines()
        .filter(|l| l.starts_with("v "))
        .take(2)
        .collect();
    assert_eq!(
        block,
        [
            "v 0.000000 0.000000 0.000000",
            "v 100.000000 0.000000 0.000000"
        ]
    );
}

#[test]
fn empty_geometry_writes_no_accessor() {
    let node = |name: &str, geometry: Vec<Geometry>| Node {
        name: name.into(),
        kind: "let".into(),
        color: dieface::die::model::PLAIN_COLOR,
        line: 1,
        children: Vec::new(),
        geometry: geometry.into_iter().map(std::sync::Arc::new).collect(),
        line_bead: None,
    };
    let scene = Scene {
        nodes: vec![
            node(
                "empty",
                vec![Geometry::Triangles {
                    positions: Vec::new(),
                    normals: Vec::new(),
                    indices: Vec::new(),
                    groups: Vec::new(),
                }],
            ),
            node(
                "point",
                vec![Geometry::LineStrip {
                    points: vec![DVec3::ZERO],
                }],
            ),
            node(
                "line",
                vec![Geometry::LineStrip {
                    points: vec![DVec3::ZERO, DVec3::X],
                }],
            ),
        ],
        tolerance_mm: 0.01,
        source_name: "hand.die".into(),
    };
    let (json, bin) = parse_glb(&encode(&scene, Format::Glb));
    let accessors = json["accessors"].as_array().unwrap();
    assert_eq!(accessors.len(), 1);
    assert!(accessors.iter().all(|a| a["count"].as_u64().unwrap() > 0));
    assert_eq!(json["meshes"].as_array().unwrap().len(), 1);
    assert!(node_named(&json, "empty").get("mesh").is_none());
    assert_eq!(bin.len(), 24);
    // Nothing at all: no buffer, no BIN chunk, still a valid document.
    let nothing = Scene {
        nodes: Vec::new(),
        tolerance_mm: 0.01,
        source_name: "empty.die".into(),
    };
    let (json, bin) = parse_glb(&encode(&nothing, Format::Glb));
    assert!(bin.is_empty());
    assert!(json.get("buffers").is_none());
    assert_eq!(json["scene"], 0);
}

#[test]
fn gltf_embeds_the_same_buffer() {
    let scene = scene_of(FEATURE);
    let glb = encode(&scene, Format::Glb);
    let (glb_json, bin) = parse_glb(&glb);
    let gltf: Json = serde_json::from_slice(&encode(&scene, Format::Gltf)).unwrap();
    let uri = gltf["buffers"][0]["uri"].as_str().unwrap();
    assert!(uri.starts_with("data:application/octet-stream;base64,"));
    assert_eq!(
        gltf["buffers"][0]["byteLength"],
        glb_json["buffers"][0]["byteLength"]
    );
    assert_eq!(gltf["nodes"], glb_json["nodes"]);
    assert_eq!(gltf["accessors"], glb_json["accessors"]);
    let declared = glb_json["buffers"][0]["byteLength"].as_u64().unwrap() as usize;
    assert!(bin.len() >= declared && bin.len() - declared < 4);
}

#[test]
fn large_meshes_use_u32_indices_small_ones_u16() {
    let triangles = |n: usize| {
        let positions: Vec<DVec3> = (0..n)
            .map(|i| DVec3::new(i as f64, (i % 7) as f64, 0.0))
            .collect();
        let last = (n - 1) as u32;
        Geometry::Triangles {
            normals: vec![DVec3::Z; n],
            positions,
            indices: vec![0, 1, last, last, 1, 2],
            groups: Vec::new(),
        }
    };
    for (n, component, size) in [(100, 5123u64, 2usize), (70_000, 5125, 4)] {
        let scene = Scene {
            nodes: vec![Node {
                name: "m".into(),
                kind: "let".into(),
                color: dieface::die::model::PLAIN_COLOR,
                line: 1,
                children: Vec::new(),
                geometry: vec![std::sync::Arc::new(triangles(n))],
                line_bead: None,
            }],
            tolerance_mm: 0.01,
            source_name: "hand.die".into(),
        };
        let (json, bin) = parse_glb(&encode(&scene, Format::Glb));
        let prim = &json["meshes"][0]["primitives"][0];
        let acc = &json["accessors"][prim["indices"].as_u64().unwrap() as usize];
        assert_eq!(acc["componentType"], component, "{n} vertices");
        let view = &json["bufferViews"][acc["bufferView"].as_u64().unwrap() as usize];
        assert_eq!(view["byteLength"].as_u64().unwrap() as usize, 6 * size);
        assert_eq!(view["target"], 34963);
        let at = view["byteOffset"].as_u64().unwrap() as usize + 2 * size;
        let third = if size == 2 {
            u32::from(u16::from_le_bytes(bin[at..at + 2].try_into().unwrap()))
        } else {
            u32::from_le_bytes(bin[at..at + 4].try_into().unwrap())
        };
        assert_eq!(third as usize, n - 1);
    }
}

#[test]
fn atomic_write_replaces_or_leaves_alone() {
    let dir = root().join("target").join("export-atomic-test");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("out.glb");
    write_atomic(&path, b"first").unwrap();
    assert_eq!(std::fs::read(&path).unwrap(), b"first");
    write_atomic(&path, b"second, longer").unwrap();
    assert_eq!(std::fs::read(&path).unwrap(), b"second, longer");
    let leftovers: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .flatten()
        .map(|e| e.file_name())
        .filter(|n| n != "out.glb")
        .collect();
    assert!(leftovers.is_empty(), "temporary files left: {leftovers:?}");

    // A directory that does not exist: an error, and nothing is created.
    let missing = dir.join("no-such-dir").join("out.glb");
    assert!(write_atomic(&missing, b"x").is_err());
    assert!(!dir.join("no-such-dir").exists());

    // A target the rename cannot replace (a non-empty directory): an error, the target
    // untouched, no temporary file left.
    let blocked = dir.join("blocked.glb");
    std::fs::create_dir_all(blocked.join("inside")).unwrap();
    assert!(write_atomic(&blocked, b"x").is_err());
    assert!(blocked.join("inside").is_dir());
    let names: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .flatten()
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .collect();
    let mut names = names;
    names.sort();
    assert_eq!(names, ["blocked.glb", "out.glb"]);
    assert_eq!(std::fs::read(&path).unwrap(), b"second, longer");
    let _ = std::fs::remove_dir_all(&dir);
}

/// `watch`'s writes (no fsync; on Linux the new file exchanged with the old one) replace
/// the file whole and leave nothing beside it, and refuse a directory like `build`'s.
#[test]
fn renamed_writes_replace_or_leave_alone() {
    use dieface::export::atomic::{write_atomic_with, Durability::Renamed};
    let dir = root().join("target").join("export-renamed-test");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("out.glb");
    // Not there yet, then over the previous file, twice.
    for text in [&b"first"[..], b"second, longer", b"third"] {
        write_atomic_with(&path, text, Renamed).unwrap();
        assert_eq!(std::fs::read(&path).unwrap(), text);
    }
    let blocked = dir.join("blocked.glb");
    std::fs::create_dir_all(blocked.join("inside")).unwrap();
    assert!(write_atomic_with(&blocked, b"x", Renamed).is_err());
    assert!(blocked.join("inside").is_dir());
    let mut names: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .flatten()
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    assert_eq!(
        names,
        ["blocked.glb", "out.glb"],
        "nothing left beside them"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// The scene cache and the glTF buffer cache (what `watch` uses) give the same bytes
/// as a fresh build after an edit, and keep the tessellations of what the edit did not
/// touch.
#[test]
fn cached_rebuild_equals_a_fresh_build() {
    use dieface::export::gltf::GltfCache;
    use dieface::export::scene::SceneCache;
    use dieface::export::{encode_with, Format};
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("examples/fender")
        .canonicalize()
        .unwrap();
    let text = std::fs::read_to_string(dir.join("fender.die")).unwrap();
    let edited = text.replace("let draft = 8 deg", "let draft = 9 deg");
    assert_ne!(text, edited);
    let tol = dieface::geom::tessellate::Tolerance::new(0.05).unwrap();

    let mut engine = dieface::eval::Engine::new(Some(dir.clone()));
    let mut cache = SceneCache::default();
    let mut encoded = GltfCache::default();
    let first = engine.evaluate("fender.die", &text, Some(dir.clone()));
    let first_scene = cache.build(&engine.die_model(&first), &tol).unwrap();
    encode_with(&first_scene, Format::Glb, &mut encoded);
    let cached_before = cache.len();
    let second = engine.evaluate("fender.die", &edited, Some(dir.clone()));
    let second_scene = cache.build(&engine.die_model(&second), &tol).unwrap();
    let warm = encode_with(&second_scene, Format::Glb, &mut encoded);
    let warm_gltf = encode_with(&second_scene, Format::Gltf, &mut encoded);
    assert_eq!(
        cache.len(),
        cached_before,
        "one sketch replaced, the rest reused"
    );

    let mut fresh_engine = dieface::eval::Engine::new(Some(dir.clone()));
    let fresh = fresh_engine.evaluate("fender.die", &edited, Some(dir));
    let cold_scene = dieface::export::build_scene(&fresh_engine.die_model(&fresh), &tol).unwrap();
    let cold = dieface::export::encode(&cold_scene, Format::Glb);
    assert!(warm == cold, "cached and fresh builds give the same bytes");
    let cold_gltf = dieface::export::encode(&cold_scene, Format::Gltf);
    assert!(warm_gltf == cold_gltf, "and the same glTF");
}

/// The fender die exports its product, every piece of the punch opening line (as line
/// strips, without repeating the closed line) and every blankholder patch as named
/// nodes, in the glTF too.
#[test]
fn the_fender_exports_product_opening_pieces_and_binder_patches() {
    let scene = scene_of_path(&root().join("examples/fender/fender.die"));
    let product = scene.find("fender").expect("the product is a node");
    assert!(matches!(*product.geometry[0], Geometry::Triangles { .. }));
    assert_eq!(product.kind, "product");

    let pieces = [
        "front",
        "front_nose",
        "nose",
        "nose_top",
        "top",
        "top_rear",
        "rear",
        "rear_front",
    ];
    let opening = scene.find("opening").expect("the punch opening is a node");
    let names: Vec<&str> = opening.children.iter().map(|n| n.name.as_str()).collect();
    let expected: Vec<String> = pieces.iter().map(|p| format!("opening/{p}")).collect();
    assert_eq!(
        names, expected,
        "one line per piece, no repeated closed line"
    );
    for child in &opening.children {
        assert_eq!(child.kind, "punch_opening");
        assert!(matches!(*child.geometry[0], Geometry::LineStrip { .. }));
    }
    // The pieces chain end to end into one closed line.
    let ends: Vec<(DVec3, DVec3)> = opening
        .children
        .iter()
        .map(|c| match &*c.geometry[0] {
            Geometry::LineStrip { points } => (points[0], points[points.len() - 1]),
            Geometry::Triangles { .. } => unreachable!("checked above"),
        })
        .collect();
    for k in 0..ends.len() {
        let next = ends[(k + 1) % ends.len()].0;
        assert!(ends[k].1.distance(next) < 1e-9, "piece {k} meets the next");
    }

    let binder = scene.find("binder").expect("the blankholder is a node");
    let names: Vec<&str> = binder.children.iter().map(|n| n.name.as_str()).collect();
    let expected: Vec<String> = pieces.iter().map(|p| format!("binder/{p}")).collect();
    assert_eq!(names, expected, "one surface patch per piece");
    for child in &binder.children {
        assert_eq!(child.kind, "blankholder");
        assert!(matches!(*child.geometry[0], Geometry::Triangles { .. }));
    }

    let (json, _) = parse_glb(&encode(&scene, Format::Glb));
    for name in ["fender", "opening", "binder"]
        .into_iter()
        .map(String::from)
        .chain(expected)
    {
        assert_eq!(node_named(&json, &name)["name"], name.as_str());
    }
    assert_eq!(
        node_named(&json, "binder/front")["extras"]["kind"],
        "blankholder"
    );
}

/// The scene cache knows geometry by its content: an edit that makes a feature run
/// again but rebuild the very same pieces (here the bead's `force` changes: only its
/// line bead's data, not its skin) tessellates nothing, and the rebuilt scene gives the
/// bytes a fresh build gives.
#[test]
fn a_rebuilt_feature_with_the_same_pieces_is_not_tessellated_again() {
    use dieface::export::scene::SceneCache;
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("examples/fender")
        .canonicalize()
        .unwrap();
    let text = std::fs::read_to_string(dir.join("fender.die")).unwrap();
    let edited = text.replacen("force = 250 ", "force = 260 ", 1);
    assert_ne!(text, edited, "the example's wheel-arch bead force");
    let tol = dieface::geom::tessellate::Tolerance::new(0.05).unwrap();

    let mut engine = dieface::eval::Engine::new(Some(dir.clone()));
    let mut cache = SceneCache::default();
    let first = engine.evaluate("fender.die", &text, Some(dir.clone()));
    cache.build(&engine.die_model(&first), &tol).unwrap();
    assert!(
        cache.last_misses() > 10,
        "a cold build tessellates every piece"
    );
    let second = engine.evaluate("fender.die", &edited, Some(dir.clone()));
    assert!(
        engine.last_evaluated().iter().any(|n| n == "wheel_arch"),
        "the bead ran again: {:?}",
        engine.last_evaluated()
    );
    let warm = cache.build(&engine.die_model(&second), &tol).unwrap();
    assert_eq!(cache.last_misses(), 0, "its skin and sections are the same");
    let bead = warm.find("wheel_arch").expect("the bead's node");
    assert_eq!(bead.line_bead.as_ref().and_then(|l| l.force), Some(260.0));

    let mut fresh_engine = dieface::eval::Engine::new(Some(dir.clone()));
    let fresh = fresh_engine.evaluate("fender.die", &edited, Some(dir));
    let cold = dieface::export::build_scene(&fresh_engine.die_model(&fresh), &tol).unwrap();
    let glb = |s: &Scene| dieface::export::encode(s, dieface::export::Format::Glb);
    assert!(
        glb(&warm) == glb(&cold),
        "cached and fresh builds give the same bytes"
    );
}

/// A fingerprint is the same for equal geometry built twice and differs when one control
/// point moves by the smallest step a double can take.
#[test]
fn fingerprints_follow_the_geometry_bits() {
    use dieface::geom::fingerprint::Fingerprint;
    use dieface::geom::interpolate::interpolate;
    use glam::DVec3;
    let points = |dz: f64| {
        vec![
            DVec3::new(0.0, 0.0, 0.0),
            DVec3::new(10.0, 2.0, 1.0),
            DVec3::new(20.0, -1.0, 2.0 + dz),
            DVec3::new(30.0, 0.0, 0.5),
        ]
    };
    let opts = dieface::geom::interpolate::Interpolation::default();
    let a = interpolate(&points(0.0), &opts).unwrap();
    let b = interpolate(&points(0.0), &opts).unwrap();
    let c = interpolate(&points(f64::EPSILON * 2.0), &opts).unwrap();
    assert_eq!(a.fingerprint(), b.fingerprint());
    assert_ne!(a, c);
    assert_ne!(a.fingerprint(), c.fingerprint());
}
