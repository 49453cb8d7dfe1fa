//! Hole filling (issue 17) timed side by side with MeshLab's "close holes", on the same
//! panel in the same run, both results measured the same way.
//!
//! `cargo run -p dieface-bench --release --bin holes` (needs `pip install pymeshlab`)
//!
//! The panel is the hole-filling tests' (`tests/common/panel.rs`): 1000 x 600 mm over
//! an analytic surface, about 53k triangles, 14 holes of 10 to 80 mm. dieface's whole
//! job (topology, loops and the outer boundary, base surfaces, meshing, joining) is one
//! call of `fill_holes`; MeshLab's is `meshing_close_holes` through pymeshlab, timed
//! inside Python around the filter alone (the mesh loaded before). MeshLab's filter
//! edits the mesh it holds; dieface is timed both ways: `fill_holes_in`, handed a copy
//! of the mesh made before the clock starts and filling it in place, and `fill_holes`,
//! which leaves its input and returns a filled copy. Each is the median of 7 runs. Both results are then read the same way: the faces each added, their
//! largest distance from the analytic surface (nodes, middles and edge midpoints), the
//! largest normal jump between an added face and the panel's face across a loop edge,
//! the smallest angle of an added face, and the free loops left. Prints markdown for
//! BENCHMARKS.md.

#[path = "../../../tests/common/panel.rs"]
mod panel;

use std::collections::{BTreeMap, BTreeSet};
use std::path::Path;
use std::process::Command;
use std::time::{Duration, Instant};

use dieface::geom::mesh::holes::{fill_holes, fill_holes_in, FillOptions, HoleChoice};
use dieface::geom::mesh::{Face, Mesh, Topology};
use dieface_bench::{median_time, read_obj, write_obj};
use glam::DVec3;

/// Runs per figure; the median is reported.
const RUNS: usize = 7;

/// What a fill added and how good it is.
#[derive(Clone)]
struct Measured {
    added: usize,
    /// The largest distance of an added face from the analytic surface (mm): all, and
    /// where the surface's smallest radius of curvature is 500 mm or more.
    deviation: f64,
    deviation_gentle: f64,
    /// The largest normal jump between an added face and the panel's face across a
    /// loop edge (deg): all, and where R >= 500 mm.
    jump: f64,
    jump_gentle: f64,
    smallest_angle: f64,
    loops_left: usize,
}

/// Whether the surface under `p` is gentle: its smallest radius of curvature at least
/// 500 mm (the goals hold there).
fn gentle(p: DVec3) -> bool {
    panel::smallest_radius(p.x, p.y) >= 500.0
}

fn measure(before: &Mesh, after: &Mesh) -> Measured {
    // The panel's own faces, by their corners' positions (a peer may renumber nodes).
    let key = |p: DVec3| {
        (
            (p.x * 1e4).round() as i64,
            (p.y * 1e4).round() as i64,
            (p.z * 1e4).round() as i64,
        )
    };
    let face_key = |m: &Mesh, f: &Face| {
        let mut k: Vec<_> = f
            .indices()
            .iter()
            .map(|&i| key(m.positions()[i as usize]))
            .collect();
        k.sort();
        k
    };
    let own: BTreeSet<_> = before.faces().iter().map(|f| face_key(before, f)).collect();
    let added: Vec<usize> = (0..after.face_count())
        .filter(|&k| !own.contains(&face_key(after, &after.faces()[k])))
        .collect();
    let corners = |k: usize| {
        let i = after.faces()[k].indices();
        [0, 1, 2].map(|c| after.positions()[i[c] as usize])
    };
    let (mut deviation, mut deviation_gentle, mut smallest) = (0.0f64, 0.0f64, 180.0f64);
    for &k in &added {
        let [a, b, c] = corners(k);
        let here_gentle = gentle((a + b + c) / 3.0);
        for p in [
            a,
            b,
            c,
            (a + b + c) / 3.0,
            (a + b) / 2.0,
            (b + c) / 2.0,
            (c + a) / 2.0,
        ] {
            let off = panel::distance_to_surface(p);
            deviation = deviation.max(off);
            if here_gentle {
                deviation_gentle = deviation_gentle.max(off);
            }
        }
        for (p, q, r) in [(a, b, c), (b, c, a), (c, a, b)] {
            smallest = smallest.min((q - p).angle_between(r - p).to_degrees());
        }
    }
    let is_added: BTreeSet<usize> = added.iter().copied().collect();
    let topology = Topology::build(after);
    let (mut jump, mut jump_gentle) = (0.0f64, 0.0f64);
    let mut edges: BTreeMap<(u32, u32), Vec<usize>> = BTreeMap::new();
    for k in 0..after.face_count() {
        let i = after.faces()[k].indices();
        for e in 0..3 {
            let (a, b) = (i[e], i[(e + 1) % 3]);
            edges.entry((a.min(b), a.max(b))).or_default().push(k);
        }
    }
    let normal = |k: usize| {
        let [a, b, c] = corners(k);
        (b - a).cross(c - a).normalize_or_zero()
    };
    for faces in edges.values() {
        if let [f, g] = faces[..] {
            if is_added.contains(&f) != is_added.contains(&g) {
                let angle = normal(f).angle_between(normal(g)).to_degrees();
                jump = jump.max(angle);
                let [a, b, c] = corners(f);
                if gentle((a + b + c) / 3.0) {
                    jump_gentle = jump_gentle.max(angle);
                }
            }
        }
    }
    Measured {
        added: added.len(),
        deviation,
        deviation_gentle,
        jump,
        jump_gentle,
        smallest_angle: smallest,
        loops_left: topology.boundary_loops().loops.len(),
    }
}

fn main() {
    let dir = std::env::temp_dir().join("dieface-bench-holes");
    std::fs::create_dir_all(&dir).expect("a temporary folder");
    let holes = panel::standard_holes();
    let mesh = panel::panel(5.0, &holes);
    let input = dir.join("panel.obj");
    write_obj(&mesh, &input, "", 12);
    let options = FillOptions {
        holes: HoleChoice::All,
        outer: None,
        size: None,
    };
    // `HOLES_PROFILE=N`: only fill the panel in place N times, for `perf record`.
    if let Some(n) = std::env::var("HOLES_PROFILE")
        .ok()
        .and_then(|n| n.parse::<usize>().ok())
    {
        for _ in 0..n {
            fill_holes_in(mesh.clone(), &options).expect("filled");
        }
        return;
    }
    let ours = median_time(
        || {
            fill_holes(&mesh, &options).expect("filled");
        },
        1,
        RUNS,
    );
    // The peer's filter edits the mesh it holds; so does `fill_holes_in`, handed a copy
    // made before its clock starts.
    let mut in_place: Vec<Duration> = (0..RUNS)
        .map(|_| {
            let copy = mesh.clone();
            let start = Instant::now();
            fill_holes_in(copy, &options).expect("filled");
            start.elapsed()
        })
        .collect();
    in_place.sort();
    let in_place = in_place[RUNS / 2];
    let filled = fill_holes(&mesh, &options).expect("filled");
    let ours_out = dir.join("dieface.obj");
    write_obj(&filled.mesh, &ours_out, "", 12);
    // MeshLab closes loops of up to so many edges: every hole's, not the outer edge's.
    let largest = filled
        .holes
        .iter()
        .map(|h| filled.free.loops[h.loop_index].nodes.len())
        .max()
        .unwrap_or(0)
        + 1;
    let outer_edges = filled
        .free
        .loops
        .iter()
        .filter(|l| l.outer)
        .map(|l| l.nodes.len())
        .min()
        .unwrap_or(0);
    assert!(
        largest < outer_edges,
        "the outer edge has more edges than any hole"
    );
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("reference/meshlab_close_holes.py");
    let ours_measured = measure(&mesh, &read_obj(&ours_out));
    let mut rows = vec![
        (
            "dieface `fill_holes_in` (the mesh filled in place)".to_string(),
            in_place.as_secs_f64() * 1e3,
            ours_measured.clone(),
        ),
        (
            "dieface `fill_holes` (a filled copy)".to_string(),
            ours.as_secs_f64() * 1e3,
            ours_measured,
        ),
    ];
    for refine in [false, true] {
        let out = dir.join(if refine {
            "meshlab_refined.obj"
        } else {
            "meshlab.obj"
        });
        let mut command = Command::new("python3");
        command
            .arg(&script)
            .arg(&input)
            .arg(&out)
            .arg(RUNS.to_string())
            .arg(largest.to_string());
        if refine {
            command.arg("refine");
        }
        let result = command.output().expect("python3 runs");
        assert!(
            result.status.success(),
            "MeshLab: {}",
            String::from_utf8_lossy(&result.stderr)
        );
        let text = String::from_utf8_lossy(&result.stdout);
        let ms: f64 = text
            .split_whitespace()
            .next()
            .and_then(|w| w.parse().ok())
            .expect("MeshLab's time");
        let name = if refine {
            "MeshLab `meshing_close_holes`, `refinehole`"
        } else {
            "MeshLab `meshing_close_holes`"
        };
        rows.push((name.to_string(), ms, measure(&mesh, &read_obj(&out))));
    }
    println!(
        "panel: {} triangles, {} nodes, {} holes (the outer edge kept)\n",
        mesh.face_count(),
        mesh.vertex_count(),
        holes.len()
    );
    println!("| filler | time (median of {RUNS}) | vs dieface | faces added | largest deviation, R >= 500 mm / all | largest normal jump at a loop, R >= 500 mm / all | smallest angle | free loops left |");
    println!("|---|---:|---:|---:|---:|---:|---:|---:|");
    let base = rows[0].1;
    for (name, ms, m) in rows {
        println!(
            "| {name} | {ms:.1} ms | {:.2}x | {} | {:.3} / {:.3} mm | {:.2} / {:.2} deg | {:.1} deg | {} |",
            ms / base,
            m.added,
            m.deviation_gentle,
            m.deviation,
            m.jump_gentle,
            m.jump,
            m.smallest_angle,
            m.loops_left
        );
    }
}
