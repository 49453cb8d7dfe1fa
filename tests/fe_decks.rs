//! The FE decks read back by readers dieface does not share code with: the LS-DYNA
//! deck by `lsdyna_mesh_reader`, the Nastran deck by pyNastran and by meshio, through
//! `tests/reference/fe_readback.py`. Everything the readers report is compared with
//! the model written: nodes (to the six written decimals), elements by id with their
//! part and nodes, counts by type and part, sections, material, and each draw bead's
//! node set, force curve and contact (the keyword cards `lsdyna_mesh_reader` does not
//! read are parsed by the script from LS-DYNA's fixed columns, and it says so).
//!
//! The Python modules are pinned in `tests/reference/fe-requirements.txt`, which
//! `scripts/test` installs. Without `python3` or a module this test fails, saying so: a
//! reader that is not there must never look like a pass.

use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::{SystemTime, UNIX_EPOCH};

use dieface::export::fe::{encode_lsdyna, encode_nastran, FeBead, FeModel, FePart, Shell};
use glam::DVec3;
use serde_json::{json, Value};

/// The exit status of `fe_readback.py` when a module is missing.
const MISSING_MODULE: i32 = 3;

/// Two parts sharing a seam of three nodes (2, 5, 8): a 2 x 2 quad patch, and a quad
/// with three triangles beside it; coordinates that are not round, one far from the
/// origin and one near zero; a bead of ten nodes (two set cards) with a force and one
/// of three without.
fn model() -> FeModel {
    let xs = [-0.000123, 250.5, 1234.567891, 1800.25, 2047.000001];
    let ys = [-9876.54321, -120.000007, 333.333333];
    let mut nodes = Vec::new();
    for (r, &y) in ys.iter().enumerate() {
        for (c, &x) in xs[..3].iter().enumerate() {
            nodes.push(DVec3::new(x, y, 12.345678 - 0.1 * (r * 3 + c) as f64));
        }
    }
    // 9, 10, 11: the binder's column beside the seam; 12: a node further out.
    for (r, &y) in ys.iter().enumerate() {
        nodes.push(DVec3::new(xs[3], y, -0.000987 * (r + 1) as f64));
    }
    nodes.push(DVec3::new(xs[4], ys[1], 7.5));
    FeModel {
        title: "fe readback: die face and binder".into(),
        nodes,
        parts: vec![
            FePart {
                name: "die face".into(),
                kind: "step_draw".into(),
                thickness: 1.25,
                shells: vec![
                    Shell::Quad([0, 1, 4, 3]),
                    Shell::Quad([1, 2, 5, 4]),
                    Shell::Quad([3, 4, 7, 6]),
                    Shell::Quad([4, 5, 8, 7]),
                ],
            },
            FePart {
                name: "binder".into(),
                kind: "blankholder".into(),
                thickness: 0.8,
                shells: vec![
                    Shell::Quad([2, 9, 10, 5]),
                    Shell::Triangle([5, 10, 11]),
                    Shell::Triangle([5, 11, 8]),
                    Shell::Triangle([9, 12, 10]),
                ],
            },
        ],
        beads: vec![
            FeBead {
                name: "front bead".into(),
                nodes: vec![0, 1, 2, 9, 12, 11, 8, 7, 6, 3],
                force: Some(187.5),
                depth: 6.0,
            },
            FeBead {
                name: "rear bead".into(),
                nodes: vec![3, 4, 5],
                force: None,
                depth: 4.5,
            },
        ],
    }
}

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// A new folder under the system's temporary folder, named by this process and the
/// clock so parallel runs never share one.
fn temp_dir() -> PathBuf {
    let nanos = SystemTime::now()
        .duration_since(UNIX_EPOCH)
        .map(|d| d.as_nanos())
        .unwrap_or(0);
    let dir = std::env::temp_dir().join(format!("dieface-fe-decks-{}-{nanos}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("a temporary folder");
    dir
}

/// `fe_readback.py` on the two decks: its JSON.
fn read_back(k: &Path, bdf: &Path) -> Value {
    let script = root()
        .join("tests")
        .join("reference")
        .join("fe_readback.py");
    let output = Command::new("python3")
        .arg(&script)
        .arg(k)
        .arg(bdf)
        .current_dir(root())
        .output()
        .unwrap_or_else(|e| {
            panic!(
                "`python3` must be on PATH to read the FE decks back ({e}): run `scripts/test`, \
                 which installs the readers of tests/reference/fe-requirements.txt"
            )
        });
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_ne!(
        output.status.code(),
        Some(MISSING_MODULE),
        "a reader of the FE decks is not installed: run `scripts/test` (it installs \
         tests/reference/fe-requirements.txt with pip), or `python3 -m pip install -r \
         tests/reference/fe-requirements.txt` once\n{stderr}"
    );
    assert!(
        output.status.success(),
        "fe_readback.py failed on {} and {}:\n{stderr}",
        k.display(),
        bdf.display()
    );
    serde_json::from_slice(&output.stdout).unwrap_or_else(|e| {
        panic!(
            "fe_readback.py printed no JSON ({e}):\n{}",
            String::from_utf8_lossy(&output.stdout)
        )
    })
}

/// Every node read back where it was written, to the written precision (six
/// decimals: half a micrometre, plus the reader's last bit).
fn assert_nodes(reader: &str, read: &Value, model: &FeModel) {
    let nodes = read.as_object().expect("nodes by id");
    assert_eq!(nodes.len(), model.nodes.len(), "{reader}: node count");
    for (i, p) in model.nodes.iter().enumerate() {
        let id = (i + 1).to_string();
        let xyz = nodes[&id].as_array().expect("x, y, z");
        for (axis, (got, want)) in xyz.iter().zip([p.x, p.y, p.z]).enumerate() {
            let got = got.as_f64().expect("a number");
            let tolerance = 5e-7 + 4.0 * f64::EPSILON * want.abs();
            assert!(
                (got - want).abs() <= tolerance,
                "{reader}: node {id} axis {axis} read {got}, written {want}"
            );
        }
    }
}

/// The shells in deck order: element id, part id, 1-based node ids.
fn shells(model: &FeModel) -> Vec<(u64, u64, &Shell, Vec<u64>)> {
    let mut out = Vec::new();
    for (k, part) in model.parts.iter().enumerate() {
        for shell in &part.shells {
            let ids = shell.nodes().iter().map(|&n| u64::from(n) + 1).collect();
            out.push((out.len() as u64 + 1, k as u64 + 1, shell, ids));
        }
    }
    out
}

/// Counts by name as a reader lists them: only the kinds present.
fn present(counts: &[(&str, usize)]) -> Value {
    Value::Object(
        counts
            .iter()
            .filter(|(_, n)| *n > 0)
            .map(|(k, n)| (k.to_string(), json!(n)))
            .collect(),
    )
}

/// The model's shells by kind (quads, triangles), and per part id.
fn counts(model: &FeModel) -> (usize, usize, Value) {
    let all = model.parts.iter().flat_map(|p| &p.shells);
    let quads = all.clone().filter(|s| matches!(s, Shell::Quad(_))).count();
    let triangles = all.count() - quads;
    let per_part: serde_json::Map<String, Value> = model
        .parts
        .iter()
        .enumerate()
        .map(|(k, p)| ((k + 1).to_string(), json!(p.shells.len())))
        .collect();
    (quads, triangles, Value::Object(per_part))
}

/// The nodes and shells lsdyna_mesh_reader read back: every one, where it was written.
fn check_lsdyna_mesh(read: &Value, model: &FeModel) {
    let (quads, triangles, per_part) = counts(model);
    assert!(
        read["reader"]
            .as_str()
            .is_some_and(|r| r.starts_with("lsdyna_mesh_reader")),
        "{}",
        read["reader"]
    );
    assert_eq!(read["node_count"], model.nodes.len());
    assert_nodes("lsdyna_mesh_reader", &read["nodes"], model);
    assert_eq!(
        read["element_counts"],
        json!({"quad": quads, "triangle": triangles, "other": 0})
    );
    assert_eq!(read["part_element_counts"], per_part);
    let elements = read["elements"].as_object().expect("elements by id");
    assert_eq!(elements.len(), quads + triangles);
    for (eid, pid, shell, mut ids) in shells(model) {
        if let Shell::Triangle(_) = shell {
            ids.push(ids[2]);
        }
        assert_eq!(
            elements[&eid.to_string()],
            json!({"part": pid, "nodes": ids}),
            "lsdyna_mesh_reader: element {eid}"
        );
    }
}

/// The nodes and shells pyNastran read back: every one, where it was written.
fn check_pynastran_mesh(read: &Value, model: &FeModel) {
    let (quads, triangles, per_part) = counts(model);
    assert!(
        read["reader"]
            .as_str()
            .is_some_and(|r| r.starts_with("pyNastran")),
        "{}",
        read["reader"]
    );
    assert_eq!(read["node_count"], model.nodes.len());
    assert_nodes("pyNastran", &read["nodes"], model);
    assert_eq!(
        read["element_counts"],
        present(&[("CQUAD4", quads), ("CTRIA3", triangles)])
    );
    assert_eq!(read["part_element_counts"], per_part);
    let elements = read["elements"].as_object().expect("elements by id");
    assert_eq!(elements.len(), quads + triangles);
    for (eid, pid, shell, ids) in shells(model) {
        let card = match shell {
            Shell::Quad(_) => "CQUAD4",
            Shell::Triangle(_) => "CTRIA3",
        };
        assert_eq!(
            elements[&eid.to_string()],
            json!({"type": card, "property": pid, "nodes": ids}),
            "pyNastran: element {eid}"
        );
    }
    assert_eq!(read["unknown_cards"], json!([]));
}

fn check_lsdyna(read: &Value, model: &FeModel) {
    check_lsdyna_mesh(read, model);
    assert_eq!(read["node_count"], 13);
    assert_eq!(read["part_element_counts"], json!({"1": 4, "2": 4}));

    let parsed = &read["parsed_by_this_script"];
    let keywords: Vec<&str> = parsed["keywords"]
        .as_array()
        .expect("keywords")
        .iter()
        .filter_map(Value::as_str)
        .collect();
    assert_eq!(
        keywords,
        [
            "*KEYWORD",
            "*TITLE",
            "*PART",
            "*PART",
            "*SECTION_SHELL",
            "*SECTION_SHELL",
            "*MAT_RIGID",
            "*NODE",
            "*ELEMENT_SHELL",
            "*SET_NODE_LIST",
            "*DEFINE_CURVE",
            "*CONTACT_DRAWBEAD",
            "*SET_NODE_LIST",
            "*CONTACT_DRAWBEAD",
            "*END",
        ]
    );
    assert_eq!(
        parsed["parts"],
        json!({
            "1": {"heading": "die face", "secid": 1, "mid": 1},
            "2": {"heading": "binder", "secid": 2, "mid": 1},
        })
    );
    assert_eq!(
        parsed["sections"],
        json!({
            "1": {"elform": 2, "thickness": [1.25, 1.25, 1.25, 1.25]},
            "2": {"elform": 2, "thickness": [0.8, 0.8, 0.8, 0.8]},
        })
    );
    assert_eq!(
        parsed["materials"],
        json!({"1": {"ro": 7.85e-9, "e": 210000.0, "pr": 0.3}})
    );
    assert_eq!(
        parsed["node_sets"],
        json!({"1": [1, 2, 3, 10, 13, 12, 9, 8, 7, 4], "2": [4, 5, 6]})
    );
    assert_eq!(
        parsed["curves"],
        json!({"1": [[0.0, 187.5], [1000.0, 187.5]]})
    );
    assert_eq!(
        parsed["drawbeads"],
        json!([
            {"ssid": 1, "msid": 1, "sstyp": 4, "mstyp": 2, "cards": 4,
             "lcidrf": 1, "lcidnf": 0, "dbdth": 6.0, "dfscl": 1.0},
            {"ssid": 2, "msid": 1, "sstyp": 4, "mstyp": 2, "cards": 4,
             "lcidrf": 0, "lcidnf": 0, "dbdth": 4.5, "dfscl": 1.0},
        ])
    );
}

fn check_pynastran(read: &Value, model: &FeModel) {
    check_pynastran_mesh(read, model);
    assert_eq!(read["element_counts"], json!({"CQUAD4": 5, "CTRIA3": 3}));
    assert_eq!(
        read["properties"],
        json!({
            "1": {"type": "PSHELL", "t": 1.25, "mid1": 1, "mid2": 1},
            "2": {"type": "PSHELL", "t": 0.8, "mid1": 1, "mid2": 1},
        })
    );
    assert_eq!(
        read["materials"],
        json!({"1": {"type": "MAT1", "e": 210000.0, "nu": 0.3, "rho": 7.85e-9}})
    );
    assert_eq!(read["unknown_cards"], json!([]));
    assert_eq!(
        read["parsed_by_this_script"]["beads"],
        json!([
            {"title": "draw bead 1: front bead", "force": 187.5,
             "nodes": [1, 2, 3, 10, 13, 12, 9, 8, 7, 4]},
            {"title": "draw bead 2: rear bead", "force": null, "nodes": [4, 5, 6]},
        ])
    );
}

fn check_meshio(read: &Value, model: &FeModel) {
    assert!(
        read["reader"]
            .as_str()
            .is_some_and(|r| r.starts_with("meshio")),
        "{}",
        read["reader"]
    );
    let (quads, triangles, _) = counts(model);
    assert_eq!(read["node_count"], model.nodes.len());
    assert_nodes("meshio", &read["nodes"], model);
    assert_eq!(
        read["cell_counts"],
        present(&[("quad", quads), ("triangle", triangles)])
    );
    let mut want = json!({
        "quad": {"ids": [], "nodes": [], "property": []},
        "triangle": {"ids": [], "nodes": [], "property": []},
    });
    for (eid, pid, shell, ids) in shells(model) {
        let kind = match shell {
            Shell::Quad(_) => "quad",
            Shell::Triangle(_) => "triangle",
        };
        for (key, value) in [
            ("ids", json!(eid)),
            ("nodes", json!(ids)),
            ("property", json!(pid)),
        ] {
            if let Some(list) = want[kind][key].as_array_mut() {
                list.push(value);
            }
        }
    }
    // A reader lists only the cell kinds the deck has.
    if let Some(kinds) = want.as_object_mut() {
        kinds.retain(|_, v| v["ids"].as_array().is_some_and(|a| !a.is_empty()));
    }
    assert_eq!(read["cells"], want);
}

#[test]
fn the_decks_read_back_as_written() {
    let model = model();
    assert_eq!(model.check(), Ok(()));
    let dir = temp_dir();
    let k = dir.join("die.k");
    let bdf = dir.join("die.bdf");
    std::fs::write(&k, encode_lsdyna(&model)).expect("write die.k");
    std::fs::write(&bdf, encode_nastran(&model)).expect("write die.bdf");

    let read = read_back(&k, &bdf);
    check_lsdyna(&read["lsdyna"], &model);
    check_pynastran(&read["nastran"], &model);
    check_meshio(&read["meshio"], &model);
    // Kept when an assertion fails above, to be looked at; removed on success.
    let _ = std::fs::remove_dir_all(&dir);
}

/// The example's die model as the build sees it, turned into the deck's data by the
/// library (the reference the decks the binary wrote are read against).
fn example_deck(example: &str) -> FeModel {
    script_deck(
        &root()
            .join("examples")
            .join(example)
            .join(format!("{example}.die")),
        example,
    )
}

/// The deck's data of the script at `path`, titled `title`, as the build makes it.
fn script_deck(path: &Path, example: &str) -> FeModel {
    let path = path.to_path_buf();
    let mut engine = dieface::eval::Engine::new(Some(root()));
    let outcome = engine.evaluate_path(&path).expect("the example reads");
    assert!(
        outcome.diagnostics.is_empty(),
        "the example evaluates cleanly"
    );
    let model = engine.die_model(&outcome);
    dieface::export::fe::from_model::fe_model(&model, example)
}

/// `dieface build SCRIPT -o K -o BDF`, which must succeed.
fn build_decks(script: &Path, k: &Path, bdf: &Path) {
    let out = Command::new(env!("CARGO_BIN_EXE_dieface"))
        .arg("build")
        .arg(script)
        .arg("-o")
        .arg(k)
        .arg("-o")
        .arg(bdf)
        .output()
        .expect("dieface runs");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

#[test]
fn a_quad_meshed_example_built_to_decks_reads_back_with_every_node_and_element() {
    let dir = temp_dir();
    let k = dir.join("door_inner.k");
    let bdf = dir.join("door_inner.bdf");
    let example = root().join("examples/door_inner_quad/door_inner_quad.die");
    build_decks(&example, &k, &bdf);
    // The same script gives the same bytes.
    let again = dir.join("again.k");
    let out = Command::new(env!("CARGO_BIN_EXE_dieface"))
        .arg("build")
        .arg(&example)
        .arg("-o")
        .arg(&again)
        .output()
        .expect("dieface runs");
    assert!(out.status.success());
    assert_eq!(
        std::fs::read(&k).expect("read"),
        std::fs::read(&again).expect("read"),
        "a second build wrote other bytes"
    );
    let model = example_deck("door_inner_quad");
    // One part, the quad mesh, nearly all quads.
    assert_eq!(model.parts.len(), 1);
    assert_eq!(model.parts[0].kind, "quad_mesh");
    let quads = model.parts[0]
        .shells
        .iter()
        .filter(|s| matches!(s, Shell::Quad(_)))
        .count();
    assert!(quads * 100 > 99 * model.parts[0].shells.len());
    let read = read_back(&k, &bdf);
    check_lsdyna_mesh(&read["lsdyna"], &model);
    check_pynastran_mesh(&read["nastran"], &model);
    check_meshio(&read["meshio"], &model);
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn the_fender_die_face_deck_reads_back_with_its_three_parts_and_two_line_beads() {
    let dir = temp_dir();
    let k = dir.join("fender.k");
    let bdf = dir.join("fender.bdf");
    let example = root().join("examples/fender/fender_deck.die");
    build_decks(&example, &k, &bdf);
    let model = script_deck(&example, "fender_deck");
    // One part per feature, the seams' nodes shared between them (fewer nodes in the
    // deck than in the three meshes), and the two beads.
    let kinds: Vec<&str> = model.parts.iter().map(|p| p.kind.as_str()).collect();
    assert_eq!(kinds, ["quad_mesh"; 3]);
    assert_eq!(model.beads.len(), 2);
    let per_part: usize = model
        .parts
        .iter()
        .map(|p| {
            p.shells
                .iter()
                .flat_map(|s| match s {
                    Shell::Quad(q) => q.to_vec(),
                    Shell::Triangle(t) => t.to_vec(),
                })
                .collect::<std::collections::BTreeSet<u32>>()
                .len()
        })
        .sum();
    // The product outline and the punch opening (some 6 m together) at 10 mm: several
    // hundred nodes in two parts each.
    let shared = per_part - model.nodes.len();
    assert!(shared > 500, "{shared} nodes shared between parts");
    let read = read_back(&k, &bdf);
    check_lsdyna_mesh(&read["lsdyna"], &model);
    check_pynastran_mesh(&read["nastran"], &model);
    check_meshio(&read["meshio"], &model);
    // The three parts and the two line beads, as this script's own parse finds them.
    let parsed = &read["lsdyna"]["parsed_by_this_script"];
    assert_eq!(parsed["parts"].as_object().map(|p| p.len()), Some(3));
    let keywords: Vec<&str> = parsed["keywords"]
        .as_array()
        .expect("keywords")
        .iter()
        .filter_map(Value::as_str)
        .collect();
    let count = |k: &str| keywords.iter().filter(|&&w| w == k).count();
    assert_eq!(count("*CONTACT_DRAWBEAD"), 2);
    assert_eq!(count("*SET_NODE_LIST"), 2);
    // Each bead contact carries its bead's depth (DBDTH): the wheel-arch bead is 6 mm
    // tall, the rear-corner bead 8 mm round its corner (the script's profiles).
    let depths: Vec<f64> = parsed["drawbeads"]
        .as_array()
        .expect("draw beads")
        .iter()
        .map(|d| d["dbdth"].as_f64().expect("DBDTH"))
        .collect();
    assert_eq!(depths.len(), 2);
    assert!((depths[0] - 6.0).abs() < 0.05, "{depths:?}");
    assert!((depths[1] - 8.0).abs() < 0.05, "{depths:?}");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn the_fender_deck_with_bead_skins_reads_back_with_a_part_per_bead_and_no_line_bead() {
    let dir = temp_dir();
    let k = dir.join("fender_beads.k");
    let bdf = dir.join("fender_beads.bdf");
    let example = root().join("examples/fender/fender_bead_deck.die");
    build_decks(&example, &k, &bdf);
    let model = script_deck(&example, "fender_bead_deck");
    // Product, step draw, binder and the two beads' skins; the beads modelled as
    // geometry, so no line bead.
    assert_eq!(model.parts.len(), 5);
    assert!(model.beads.is_empty());
    let read = read_back(&k, &bdf);
    check_lsdyna_mesh(&read["lsdyna"], &model);
    check_pynastran_mesh(&read["nastran"], &model);
    check_meshio(&read["meshio"], &model);
    let parsed = &read["lsdyna"]["parsed_by_this_script"];
    assert_eq!(parsed["parts"].as_object().map(|p| p.len()), Some(5));
    let _ = std::fs::remove_dir_all(&dir);
}
