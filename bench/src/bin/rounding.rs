//! The S-rail's rounds (issue 16) timed step by step, at growing mesh densities.
//!
//! `cargo run -p dieface-bench --release --bin rounding`
//!
//! Evaluates `examples/s_rail/s_rail.die` at `density` 1, 2, 4 and 6 (2,592 to 93,312
//! triangles in the sharp rail) through the library, then times, each as the median of
//! seven runs: the curvature pass over the whole sharp rail and over the rounded one
//! (what `reround` reads its round from), the die shoulder's round at a constant
//! 7.5 mm (chain, base meshes, spine, balls, loft, cut and stitch), and the round found
//! again and widened to 8-15-8 mm (the curvature of the nodes the search for the round
//! reads, finding it, the base meshes and the round). Prints markdown for BENCHMARKS.md. The whole `dieface build`
//! is timed with hyperfine beside it (see BENCHMARKS.md).

use std::path::Path;
use std::time::{Duration, Instant};

use dieface::eval::{Data, Engine, Value};
use dieface::geom::mesh::curvature::{node_curvatures, CurvatureAt};
use dieface::geom::mesh::rounding::chain::{
    chain_through, nearest_sharp_node, sharp_edges, DEFAULT_FEATURE_ANGLE,
};
use dieface::geom::mesh::rounding::existing::{find_round, reround_site, DEFAULT_BAND};
use dieface::geom::mesh::rounding::polyline_nearest;
use dieface::geom::mesh::rounding::radius::RadiusLaw;
use dieface::geom::mesh::rounding::round::{round_chain, round_site, Rounded};
use dieface::geom::mesh::{Mesh, Topology, VertexId};
use glam::DVec3;

/// Runs per figure; the median is reported.
const RUNS: usize = 7;

/// The median time of `RUNS` calls of `f`, and its last result.
fn median<T>(mut f: impl FnMut() -> T) -> (Duration, T) {
    let mut times = Vec::with_capacity(RUNS);
    let mut last = None;
    for _ in 0..RUNS {
        let start = Instant::now();
        let out = f();
        times.push(start.elapsed());
        last = Some(out);
    }
    times.sort();
    (times[RUNS / 2], last.expect("RUNS > 0"))
}

fn ms(d: Duration) -> String {
    format!("{:.1} ms", d.as_secs_f64() * 1e3)
}

/// The example's values at `density`.
fn evaluate(density: usize) -> Vec<(String, Value)> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../examples/s_rail");
    let text = std::fs::read_to_string(root.join("s_rail.die")).expect("the example");
    let text = text.replace("param density = 1 ", &format!("param density = {density} "));
    let dir = std::env::temp_dir().join(format!("dieface-bench-rounding-{density}"));
    std::fs::create_dir_all(&dir).expect("a temporary folder");
    let path = dir.join("s_rail.die");
    std::fs::write(&path, text).expect("the script written");
    let mut engine = Engine::new(Some(dir));
    let outcome = engine.evaluate_path(&path).expect("readable");
    assert!(outcome.diagnostics.is_empty(), "the example evaluates");
    outcome
        .decls
        .iter()
        .filter_map(|d| d.value.clone().map(|v| (d.name.clone(), v)))
        .collect()
}

fn value<'a>(values: &'a [(String, Value)], name: &str) -> &'a Value {
    &values.iter().find(|(n, _)| n == name).expect("declared").1
}

fn main() {
    println!(
        "| density | sharp rail triangles | curvature pass, sharp rail | constant round (7.5 mm) | rounded mesh triangles | curvature pass, rounded | find and widen (8-15-8 mm) |"
    );
    println!("|---:|---:|---:|---:|---:|---:|---:|");
    for density in [1, 2, 4, 6] {
        let values = evaluate(density);
        let Data::Mesh(rail) = &value(&values, "rail").data else {
            panic!("the rail is a mesh")
        };
        let Data::Record(record) = &value(&values, "shoulder").data else {
            panic!("the shoulder is a record")
        };
        let shoulder: &Rounded = record.model().expect("a round");
        let (curv_rail, _) = median(|| node_curvatures(rail));
        // The constant round as the `round` block runs it.
        let line = &shoulder.trim_lines[0];
        let pick = line[line.len() / 2];
        let (constant, rounded) = median(|| {
            let mesh = rail.triangulated();
            let topology = Topology::build(&mesh);
            let sharp = sharp_edges(&mesh, &topology, DEFAULT_FEATURE_ANGLE);
            let (node, _) = nearest_sharp_node(&mesh, &topology, &sharp, pick).expect("a node");
            let chain = chain_through(&mesh, &topology, &sharp, node, None).expect("a chain");
            round_chain(&mesh, &topology, &chain, &RadiusLaw::constant(7.5), 0.01).expect("rounded")
        });
        let rounded_mesh: &Mesh = &rounded.mesh;
        let (curv_round, _) = median(|| node_curvatures(rounded_mesh));
        // The re-round as the `reround` block runs it.
        let (mid_u, mid_v) = {
            let (u0, u1) = shoulder.surface.domain_u();
            let (v0, v1) = shoulder.surface.domain_v();
            (0.5 * (u0 + u1), 0.5 * (v0 + v1))
        };
        let on_round = shoulder.surface.point_at(mid_u, mid_v);
        let mesh = &shoulder.mesh;
        let (widen, widened) = median(|| {
            let topology = Topology::build(mesh);
            let node = (0..mesh.vertex_count())
                .min_by(|&a, &b| {
                    let d = |i: usize| mesh.positions()[i].distance(on_round);
                    d(a).total_cmp(&d(b))
                })
                .expect("nodes");
            let curvatures = CurvatureAt::new(mesh, &topology);
            let found = find_round(
                mesh,
                &topology,
                &|v| curvatures.at(v),
                VertexId(node as u32),
                DEFAULT_BAND,
            )
            .expect("the round");
            let length = found.length();
            let at = |s: f64| polyline_nearest(&found.guide, point_along(&found.guide, s)).1;
            let law = RadiusLaw::through(
                &[(at(0.0), 8.0), (at(0.5 * length), 15.0), (at(length), 8.0)],
                length,
                false,
            )
            .expect("radii");
            let site = reround_site(mesh, &topology, &found, law.mean(length)).expect("a site");
            round_site(mesh, &topology, &site, &law, 0.01).expect("widened")
        });
        println!(
            "| {density} | {} | {} | {} | {} | {} | {} |",
            rail.face_count(),
            ms(curv_rail),
            ms(constant),
            rounded_mesh.face_count(),
            ms(curv_round),
            ms(widen),
        );
        eprintln!(
            "density {density}: constant round {} balls, widened {} balls, {} faces",
            rounded.balls.len(),
            widened.balls.len(),
            widened.mesh.face_count()
        );
    }
}

/// The point `s` along the polyline `line`.
fn point_along(line: &[DVec3], s: f64) -> DVec3 {
    let mut run = 0.0;
    for w in line.windows(2) {
        let d = w[0].distance(w[1]);
        if run + d >= s && d > 0.0 {
            return w[0].lerp(w[1], (s - run) / d);
        }
        run += d;
    }
    line[line.len() - 1]
}
