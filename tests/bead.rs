//! Draw beads on the fender's blankholder (issue 7, in progress): the feet lie on the
//! binder, measured independently of the kernel's own height field; a bead that
//! leaves the binder or crosses the punch opening is refused at its centre line.

use std::path::{Path, PathBuf};

use dieface::eval::value::Feature;
use dieface::eval::{Data, Engine, Outcome, Value};
use dieface::geom::intersect::intersect_line_surface_all;
use glam::DVec3;

fn dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/fender")
}

/// The fender example with `extra` appended, evaluated.
fn fender_with(extra: &str) -> (Engine, Outcome) {
    let text = std::fs::read_to_string(dir().join("fender.die")).expect("the example");
    let mut engine = Engine::new(Some(dir()));
    let out = engine.evaluate("fender.die", &format!("{text}\n{extra}"), Some(dir()));
    (engine, out)
}

fn value<'a>(out: &'a Outcome, name: &str) -> &'a Value {
    out.decls
        .iter()
        .find(|d| d.name == name)
        .and_then(|d| d.value.as_ref())
        .unwrap_or_else(|| panic!("`{name}` has a value"))
}

const PROFILE: &str = "
let bead_profile = sketch(profile) {
    from (-14, 0)
    line to (-6, 6)
    fillet 3
    line to (6, 6)
    fillet 3
    line to (14, 0)
}
";

/// A straight bead along the front side and one following the rear-front corner: both
/// feet lie on the binder within 0.001 mm, measured by intersecting vertical lines with
/// every binder patch.
#[test]
fn bead_feet_lie_on_the_binder() {
    let extra = format!(
        "{PROFILE}
bead front_bead {{
    binder = binder
    line = sketch(top) {{ from (-420, -575); line to (420, -585) }}
    profile = bead_profile
    taper = 40 mm
    force = 250
}}
bead corner_bead {{
    binder = binder
    line = sketch(top) {{
        from (-775, 150)
        line to (-775, -560)
        fillet 110
        line to (-300, -580)
    }}
    profile = bead_profile
}}
"
    );
    let (engine, out) = fender_with(&extra);
    let problems: Vec<String> = out
        .diagnostics
        .iter()
        .map(|d| engine.sources.render(d, false))
        .collect();
    assert!(problems.is_empty(), "{}", problems.join("\n"));
    let Data::Record(binder) = &value(&out, "binder").data else {
        panic!("the binder is a record")
    };
    let Some(Feature::Blankholder(binder)) = &binder.feature else {
        panic!("a blankholder")
    };
    for name in ["front_bead", "corner_bead"] {
        let Data::Record(r) = &value(&out, name).data else {
            panic!("a bead is a record")
        };
        let Some(Feature::Bead(bead)) = &r.feature else {
            panic!("a bead")
        };
        let s = &bead.surface;
        let (u0, u1) = s.domain_u();
        let (v0, v1) = s.domain_v();
        let mut worst: f64 = 0.0;
        for u in [u0, u1] {
            for i in 0..=500 {
                let p = s.point_at(u, v0 + (v1 - v0) * i as f64 / 500.0);
                let below: Vec<f64> = binder
                    .patches
                    .iter()
                    .flat_map(|patch| {
                        intersect_line_surface_all(p, DVec3::Z, &patch.surface)
                            .expect("a vertical line")
                            .into_iter()
                            .map(|h| h.point.z)
                    })
                    .collect();
                let gap = below
                    .iter()
                    .map(|z| (p.z - z).abs())
                    .fold(f64::INFINITY, f64::min);
                assert!(
                    gap.is_finite(),
                    "{name}: a foot point has no binder under it"
                );
                worst = worst.max(gap);
            }
        }
        eprintln!(
            "{name}: foot gap {worst:.2e} mm, kernel's {:.2e} mm",
            bead.quality.foot_gap
        );
        assert!(worst <= 0.001, "{name}: foot gap {worst} mm");
        // The line bead: points every 15 mm along the centre line, on the binder.
        let pts = &bead.line_points;
        let steps: Vec<f64> = pts.windows(2).map(|w| w[0].distance(w[1])).collect();
        let longest = steps.iter().cloned().fold(0.0, f64::max);
        assert!(
            longest <= 15.0 + 1e-6,
            "{name}: a line-bead step of {longest} mm"
        );
    }
    let Data::Record(r) = &value(&out, "front_bead").data else {
        panic!("a record")
    };
    let Some(line_bead) = r.get("line_bead") else {
        panic!("the line bead is a field")
    };
    let Data::Record(lb) = &line_bead.data else {
        panic!("a record")
    };
    assert!(
        lb.get("force").is_some(),
        "the restraining force rides along"
    );
}

/// A centre line that leaves the binder, and one that crosses the punch opening, are
/// refused with the line as the culprit.
#[test]
fn beads_off_the_binder_are_refused() {
    for (line, words) in [
        (
            "sketch(top) { from (-420, -575); line to (420, -900) }",
            "leaves the binder",
        ),
        (
            "sketch(top) { from (-420, -575); line to (0, -300) }",
            "crosses the punch opening",
        ),
    ] {
        let extra = format!(
            "{PROFILE}
bead bad {{
    binder = binder
    line = {line}
    profile = bead_profile
}}
"
        );
        let (_, out) = fender_with(&extra);
        let d = out
            .diagnostics
            .iter()
            .find(|d| d.code == "die::bead")
            .unwrap_or_else(|| panic!("a bead diagnostic for {line}"));
        assert!(d.message.contains(words), "{}", d.message);
    }
}

/// The line bead reaches forming simulation through the glTF: the bead's node carries
/// its points (press mm), spacing and force in `extras.line_bead`.
#[test]
fn line_beads_are_in_the_gltf_extras() {
    use dieface::export::{build_scene, encode, Format};
    use dieface::geom::tessellate::Tolerance;
    let extra = format!(
        "{PROFILE}
bead front_bead {{
    binder = binder
    line = sketch(top) {{ from (-420, -575); line to (420, -585) }}
    profile = bead_profile
    line_spacing = 20 mm
    force = 250
}}
"
    );
    let (engine, out) = fender_with(&extra);
    assert!(out.diagnostics.is_empty());
    let scene = build_scene(
        &out,
        &engine.sources,
        &Tolerance::new(0.05).expect("tolerance"),
    )
    .expect("the scene builds");
    let glb = encode(&scene, Format::Glb);
    let len = u32::from_le_bytes(glb[12..16].try_into().expect("4 bytes")) as usize;
    let json: serde_json::Value = serde_json::from_slice(&glb[20..20 + len]).expect("JSON chunk");
    let node = json["nodes"]
        .as_array()
        .expect("nodes")
        .iter()
        .find(|n| n["name"] == "front_bead")
        .expect("the bead is a node");
    let lb = &node["extras"]["line_bead"];
    assert_eq!(lb["force_n_per_mm"], 250.0);
    assert_eq!(lb["spacing_mm"], 20.0);
    let points = lb["points_mm"].as_array().expect("points");
    let Data::Record(r) = &value(&out, "front_bead").data else {
        panic!("a record")
    };
    let Some(Feature::Bead(bead)) = &r.feature else {
        panic!("a bead")
    };
    assert_eq!(points.len(), bead.line_points.len());
    assert!(points.len() >= 840 / 20, "about one point every 20 mm");
    for (p, q) in points.iter().zip(&bead.line_points) {
        let x = p[0].as_f64().expect("a number");
        assert!((x - q.x).abs() < 1e-9);
    }
}
