//! The STEP export of both examples: structurally sound (every reference defined, each
//! edge used once or twice, one closed free boundary on the die face, the binder's
//! outer edge), deterministic, and in agreement with what OpenCascade read from it
//! (`tests/data/step_reference.json`, from `tests/reference/step_reference.py`).

use std::collections::{BTreeMap, BTreeSet};
use std::path::Path;

use dieface::die::blankholder::Blankholder;
use dieface::eval::value::Data;
use dieface::eval::Engine;
use dieface::export::step::{encode_step, real, StepModel};
use dieface::geom::sew::{sew, Shell, DIE_FACE_TOLERANCE};
use serde_json::Value as Json;

#[path = "common/script.rs"]
mod script;

/// One example's die face: the sewn shells and the binder's outer edge length.
struct Example {
    die: Shell,
    beads: Shell,
    binder_outer: f64,
}

fn example(name: &str) -> Example {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("examples")
        .join(name);
    let text = std::fs::read_to_string(root.join(format!("{name}.die"))).unwrap();
    let mut engine = Engine::new(None);
    let outcome = engine.evaluate(&format!("{name}.die"), &text, None);
    let values = script::clean_values(&engine, &outcome);
    let binder_outer = values
        .iter()
        .filter_map(|(_, v)| match &v.data {
            Data::Record(r) => r
                .model::<Blankholder>()
                .map(|bh| bh.patches.iter().map(|p| p.outer.length()).sum::<f64>()),
            _ => None,
        })
        .sum();
    let faces = engine.die_model(&outcome).die_face;
    Example {
        die: sew(faces.faces, DIE_FACE_TOLERANCE).unwrap(),
        beads: sew(faces.beads, DIE_FACE_TOLERANCE).unwrap(),
        binder_outer,
    }
}

fn encode(name: &str, ex: &Example) -> String {
    let bytes = encode_step(&StepModel {
        name: name.into(),
        shells: vec![("die_face".into(), &ex.die), ("beads".into(), &ex.beads)],
        uncertainty: DIE_FACE_TOLERANCE,
    });
    String::from_utf8(bytes).unwrap()
}

/// `#n=BODY;` entities of a STEP file's data section.
fn entities(text: &str) -> BTreeMap<usize, String> {
    let data = text.split("DATA;\n").nth(1).unwrap();
    let data = data.split("ENDSEC;").next().unwrap();
    data.lines()
        .map(|l| {
            let (id, body) = l.split_once('=').unwrap();
            (
                id.trim_start_matches('#').parse().unwrap(),
                body.trim_end_matches(';').to_string(),
            )
        })
        .collect()
}

fn refs(body: &str) -> Vec<usize> {
    let mut out = Vec::new();
    let b = body.as_bytes();
    let mut i = 0;
    while i < b.len() {
        if b[i] == b'#' {
            let j = (i + 1..b.len())
                .find(|&j| !b[j].is_ascii_digit())
                .unwrap_or(b.len());
            out.push(body[i + 1..j].parse().unwrap());
            i = j;
        } else {
            i += 1;
        }
    }
    out
}

/// The free edges of a shell form closed loops (every vertex met twice): their total
/// length.
fn free_loop_length(shell: &Shell) -> f64 {
    let free = shell.free_edges();
    let mut degree: BTreeMap<usize, usize> = BTreeMap::new();
    for &e in &free {
        *degree.entry(shell.edges[e].start).or_default() += 1;
        *degree.entry(shell.edges[e].end).or_default() += 1;
    }
    assert!(
        degree.values().all(|&d| d % 2 == 0),
        "the free boundary is not closed"
    );
    free.iter().map(|&e| shell.edges[e].curve.length()).sum()
}

fn check_structure(name: &str) {
    let ex = example(name);
    let text = encode(name, &ex);
    assert!(text.starts_with("ISO-10303-21;\nHEADER;\n"));
    assert!(text.ends_with("ENDSEC;\nEND-ISO-10303-21;\n"));
    let ents = entities(&text);
    // Numbered 1..n without gaps, every reference defined.
    assert_eq!(
        ents.keys().copied().collect::<Vec<_>>(),
        (1..=ents.len()).collect::<Vec<_>>()
    );
    for (id, body) in &ents {
        for r in refs(body) {
            assert!(
                ents.contains_key(&r),
                "#{id} refers to #{r}, which is not defined"
            );
        }
    }
    // Every edge is used by one oriented edge (free) or two in opposite directions.
    let edge_ids: BTreeSet<usize> = ents
        .iter()
        .filter(|(_, b)| b.starts_with("EDGE_CURVE("))
        .map(|(id, _)| *id)
        .collect();
    let mut uses: BTreeMap<usize, Vec<bool>> = BTreeMap::new();
    for body in ents.values().filter(|b| b.starts_with("ORIENTED_EDGE(")) {
        let r = refs(body);
        assert_eq!(r.len(), 1);
        assert!(edge_ids.contains(&r[0]));
        uses.entry(r[0]).or_default().push(body.ends_with(".T.)"));
    }
    assert_eq!(uses.len(), edge_ids.len(), "every edge is used");
    let shared = uses.values().filter(|u| u.len() == 2).count();
    for u in uses.values() {
        assert!(u.len() <= 2, "an edge used by more than two faces");
        if u.len() == 2 {
            assert_ne!(u[0], u[1], "a shared edge is used the same way twice");
        }
    }
    // One face per sewn face, two shells.
    let faces = ents
        .values()
        .filter(|b| b.starts_with("ADVANCED_FACE("))
        .count();
    assert_eq!(faces, ex.die.faces.len() + ex.beads.faces.len());
    assert_eq!(
        ents.values()
            .filter(|b| b.starts_with("OPEN_SHELL("))
            .count(),
        2
    );
    // The die face: every face has shared edges, and the only free boundary is the
    // binder's outer edge.
    assert!(
        shared > ex.die.faces.len(),
        "{name}: only {shared} shared edges"
    );
    for f in &ex.die.faces {
        let uses = ex.die.edge_uses();
        assert!(
            f.bound.iter().any(|&(e, _)| uses[e] == 2),
            "{name}: face {} is not sewn to anything",
            f.face.name
        );
    }
    let free = free_loop_length(&ex.die);
    assert!(
        (free - ex.binder_outer).abs() <= 1e-6 * ex.binder_outer,
        "{name}: free boundary {free} mm, binder outer edge {} mm",
        ex.binder_outer
    );
    // Deterministic: the same model gives the same bytes.
    assert_eq!(text, encode(name, &example(name)));
}

#[test]
fn the_fender_step_file_is_structurally_sound() {
    check_structure("fender");
}

#[test]
fn the_door_step_file_is_structurally_sound() {
    check_structure("door_outer");
}

#[test]
fn step_reals_have_a_decimal_point_and_round_trip() {
    for x in [
        0.0,
        -0.0,
        1.0,
        -2.5,
        1e-7,
        1.25e21,
        123.456,
        -40.187313783388795,
    ] {
        let s = real(x);
        assert!(s.contains('.'), "{s}");
        let back: f64 = s.replace("E", "e").parse().unwrap();
        assert_eq!(back, x, "{s}");
    }
    assert_eq!(real(1.0), "1.");
    assert_eq!(real(-0.0), "0.");
    assert_eq!(real(1e-7), "1.E-7");
}

/// What OpenCascade read from the STEP files (committed), against dieface now.
#[test]
fn opencascade_read_one_valid_die_face_shell_with_dieface_area() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/step_reference.json");
    let reference: Json = serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap();
    for name in ["fender", "door_outer"] {
        let ex = example(name);
        let occ = &reference["examples"][name];
        assert_eq!(
            occ["valid"],
            Json::Bool(true),
            "{name}: OpenCascade found it invalid"
        );
        let shells = occ["shells"].as_array().unwrap();
        let die = &shells[0];
        assert_eq!(
            die["faces"].as_u64().unwrap() as usize,
            ex.die.faces.len(),
            "{name}"
        );
        assert_eq!(die["valid"], Json::Bool(true), "{name}");
        assert!(
            die["free_open"].as_array().unwrap().is_empty(),
            "{name}: open free wires"
        );
        let closed = die["free_closed"].as_array().unwrap();
        assert_eq!(closed.len(), 1, "{name}: one closed free boundary");
        let free = closed[0].as_f64().unwrap();
        assert!(
            (free - ex.binder_outer).abs() <= 1e-6 * ex.binder_outer,
            "{name}: OpenCascade's free boundary {free} mm, binder outer edge {} mm",
            ex.binder_outer
        );
        let area = die["area"].as_f64().unwrap();
        let ours = ex.die.area();
        assert!(
            (area - ours).abs() <= 1e-6 * ours,
            "{name}: OpenCascade area {area} mm², dieface {ours} mm² ({:e} relative)",
            (area - ours).abs() / ours
        );
        // The beads: OpenCascade splits the bead shell into one shell per bead (they do
        // not touch); together they have the beads' area.
        let bead_area: f64 = shells[1..]
            .iter()
            .map(|s| s["area"].as_f64().unwrap())
            .sum();
        assert_eq!(
            shells.len() - 1,
            ex.beads.faces.len(),
            "{name}: bead shells"
        );
        assert!(
            (bead_area - ex.beads.area()).abs() <= 1e-6 * ex.beads.area(),
            "{name}: bead area {bead_area} vs {}",
            ex.beads.area()
        );
    }
}
