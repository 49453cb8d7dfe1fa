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
//! which leaves its input and returns a filled copy. They are timed turn about, 15
//! rounds (see `side_by_side`), so the ratio is read round by round on a machine whose
//! speed drifts; each time is the median of its 15. MeshLab with
//! `refinehole` as well is timed in its own 7 runs. Both results are then read the
//! same way: the faces each added, their
//! largest distance from the analytic surface (nodes, middles and edge midpoints), the
//! largest normal jump between an added face and the panel's face across a loop edge,
//! the smallest angle of an added face, and the free loops left. Prints markdown for
//! BENCHMARKS.md.

#[path = "../../../tests/common/panel.rs"]
mod panel;

use std::collections::{BTreeMap, BTreeSet};
use std::io::{BufRead, BufReader, Write};
use std::path::Path;
use std::process::{Command, Stdio};
use std::time::Instant;

use dieface::geom::mesh::holes::{fill_holes, fill_holes_in, FillOptions, HoleChoice};
use dieface::geom::mesh::{Face, Mesh, Topology};
use dieface_bench::{median, read_obj, write_obj};
use glam::DVec3;

/// Runs of MeshLab with `refinehole`, timed on its own; the median is reported.
const RUNS: usize = 7;

/// Rounds of the side-by-side timing (see [`side_by_side`]).
const ROUNDS: usize = 15;

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

/// Each stage of `fill_holes` timed alone, one thread, summed over the holes: where
/// the time goes.
fn stages(mesh: &Mesh) {
    use dieface::geom::mesh::holes::base::base_surface;
    use dieface::geom::mesh::holes::loops::scan;
    use dieface::geom::mesh::holes::patch::mesh_region;
    use dieface::geom::mesh::holes::plane::loop_plane;
    use dieface::geom::mesh::holes::trim::trim_loop;
    use dieface::geom::mesh::stars::VertexStars;
    use glam::DVec2;
    // The least and the median of 41 runs: on a machine shared with other work the
    // least is the nearer to what the stage costs alone.
    let time = |label: &str, f: &mut dyn FnMut()| {
        let mut times: Vec<f64> = (0..41)
            .map(|_| {
                let start = Instant::now();
                f();
                start.elapsed().as_secs_f64() * 1e3
            })
            .collect();
        times.sort_by(f64::total_cmp);
        println!(
            "{label:<28} {:>8.3} ms least, {:>8.3} ms median",
            times[0], times[20]
        );
    };
    time("stars", &mut || {
        std::hint::black_box(VertexStars::build(mesh));
    });
    time("scan (stars, pieces, loops)", &mut || {
        std::hint::black_box(scan(mesh, None));
    });
    let found = scan(mesh, None);
    let holes: Vec<_> = found.free.loops.iter().filter(|l| !l.outer).collect();
    let points: Vec<Vec<DVec3>> = holes
        .iter()
        .map(|l| {
            l.nodes
                .iter()
                .map(|v| mesh.positions()[v.index()])
                .collect()
        })
        .collect();
    let planes: Vec<_> = holes
        .iter()
        .zip(&points)
        .map(|(l, p)| {
            let normals: Vec<DVec3> = l
                .nodes
                .iter()
                .map(|&v| mesh.vertex_normal(v, found.stars.faces(v)))
                .collect();
            loop_plane(p, &normals).expect("a plane")
        })
        .collect();
    let sizes: Vec<f64> = holes
        .iter()
        .map(|l| l.length / l.nodes.len() as f64)
        .collect();
    time("base surfaces", &mut || {
        for (k, l) in holes.iter().enumerate() {
            std::hint::black_box(base_surface(&found.stars, &l.nodes, &planes[k], sizes[k]).ok());
        }
    });
    let bases: Vec<_> = (0..holes.len())
        .map(|k| base_surface(&found.stars, &holes[k].nodes, &planes[k], sizes[k]).expect("a base"))
        .collect();
    time("trim loops", &mut || {
        for k in 0..holes.len() {
            std::hint::black_box(trim_loop(&bases[k], &points[k]));
        }
    });
    let loops: Vec<Vec<DVec2>> = (0..holes.len())
        .map(|k| {
            trim_loop(&bases[k], &points[k])
                .iter()
                .rev()
                .map(|t| t.0)
                .collect()
        })
        .collect();
    time("regions meshed", &mut || {
        for k in 0..holes.len() {
            std::hint::black_box(mesh_region(&loops[k], sizes[k]).ok());
        }
    });
    let regions: Vec<_> = (0..holes.len())
        .map(|k| mesh_region(&loops[k], sizes[k]).expect("meshed"))
        .collect();
    time("mapped to the surfaces", &mut || {
        for k in 0..holes.len() {
            let r = &regions[k];
            let mapped: Vec<DVec3> = r.uv[r.boundary..]
                .iter()
                .map(|&q| bases[k].point_at(q))
                .collect();
            std::hint::black_box(mapped);
        }
    });
    let options = FillOptions {
        holes: HoleChoice::All,
        outer: None,
        size: None,
    };
    time("whole (fill_holes_in)", &mut || {
        std::hint::black_box(fill_holes_in(mesh.clone(), &options).ok());
    });
    time("clone of the mesh", &mut || {
        std::hint::black_box(mesh.clone());
    });
    let nodes: usize = holes.iter().map(|l| l.nodes.len()).sum();
    let inner: usize = regions.iter().map(|r| r.uv.len() - r.boundary).sum();
    let grid: usize = bases.iter().map(|b| b.known_nodes + b.solved_nodes).sum();
    let solved: usize = bases.iter().map(|b| b.solved_nodes).sum();
    println!(
        "{} holes, {nodes} loop nodes, {inner} inner nodes, {grid} grid nodes ({solved} solved)",
        holes.len()
    );
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
    // `HOLES_STAGES=1`: each stage of the fill timed alone on one thread (medians).
    if std::env::var("HOLES_STAGES").is_ok() {
        stages(&mesh);
        return;
    }
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
    let meshlab_out = dir.join("meshlab.obj");
    let rounds = side_by_side(&mesh, &options, &script, &input, &meshlab_out, largest);
    let mut rows = vec![
        (
            "dieface `fill_holes_in` on the mesh just read, as MeshLab is run".to_string(),
            median(&rounds.after_read),
            ours_measured.clone(),
        ),
        (
            "dieface `fill_holes` (a filled copy), after one fill".to_string(),
            median(&rounds.copy),
            ours_measured.clone(),
        ),
        (
            "dieface `fill_holes_in` (the mesh filled in place), after two fills".to_string(),
            median(&rounds.in_place),
            ours_measured,
        ),
        (
            "MeshLab `meshing_close_holes`".to_string(),
            median(&rounds.meshlab),
            measure(&mesh, &read_obj(&meshlab_out)),
        ),
    ];
    // MeshLab refining the new faces as well, in its own runs: a slower peer, kept for
    // its figures.
    let refined_out = dir.join("meshlab_refined.obj");
    let result = Command::new("python3")
        .arg(&script)
        .arg(&input)
        .arg(&refined_out)
        .arg(RUNS.to_string())
        .arg(largest.to_string())
        .arg("refine")
        .output()
        .expect("python3 runs");
    assert!(
        result.status.success(),
        "MeshLab: {}",
        String::from_utf8_lossy(&result.stderr)
    );
    let refined_ms: f64 = String::from_utf8_lossy(&result.stdout)
        .split_whitespace()
        .next()
        .and_then(|w| w.parse().ok())
        .expect("MeshLab's time");
    rows.push((
        format!("MeshLab `meshing_close_holes`, `refinehole` (its own {RUNS} runs, median)"),
        refined_ms,
        measure(&mesh, &read_obj(&refined_out)),
    ));
    println!(
        "panel: {} triangles, {} nodes, {} holes (the outer edge kept)\n",
        mesh.face_count(),
        mesh.vertex_count(),
        holes.len()
    );
    println!("| filler | time (median of {ROUNDS} rounds) | vs dieface | faces added | largest deviation, R >= 500 mm / all | largest normal jump at a loop, R >= 500 mm / all | smallest angle | free loops left |");
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
    let ratio = |ours: &[f64]| {
        let ratios: Vec<f64> = (0..ROUNDS).map(|r| rounds.meshlab[r] / ours[r]).collect();
        let (least, most) = ratios.iter().fold((f64::INFINITY, 0.0f64), |(lo, hi), &x| {
            (lo.min(x), hi.max(x))
        });
        format!("median {:.1}x, {least:.1}x to {most:.1}x", median(&ratios))
    };
    println!(
        "\nMeshLab / dieface `fill_holes_in`, round by round ({ROUNDS} rounds): on the mesh just read {}; after two fills {}",
        ratio(&rounds.after_read),
        ratio(&rounds.in_place)
    );
}

/// The side-by-side timing's rounds: each fill's time in each round (ms).
struct Rounds {
    /// `fill_holes_in` on the mesh read from the OBJ file just before, as MeshLab's
    /// filter is run (and as `dieface build` fills a mesh its script has just read).
    after_read: Vec<f64>,
    /// `fill_holes`, right after the first.
    copy: Vec<f64>,
    /// `fill_holes_in` again, right after that, on a copy of the mesh made just before:
    /// fills run back to back, the machine kept busy.
    in_place: Vec<f64>,
    meshlab: Vec<f64>,
}

/// MeshLab's `meshing_close_holes` and dieface's `fill_holes_in` and `fill_holes` timed
/// turn about, [`ROUNDS`] rounds: on a machine whose speed drifts, each round's runs
/// meet it in the same state, so the ratio read round by round holds where either's
/// own median moves.
///
/// A round is MeshLab's run, then `fill_holes_in`, `fill_holes` and `fill_holes_in`
/// again, one after another. MeshLab runs in one Python process for all rounds
/// (`serve`), which reads the OBJ file afresh before each run's clock starts, and so
/// does dieface's first run: each filter meets a mesh just read, on one thread. The
/// last run fills a copy made just before it, right after two fills: fills run back
/// to back. Both `fill_holes_in` runs fill their mesh in place (MeshLab's filter edits
/// the mesh it holds), handed it before the clock starts. MeshLab's last result is
/// written to `out`.
fn side_by_side(
    mesh: &Mesh,
    options: &FillOptions,
    script: &Path,
    input: &Path,
    out: &Path,
    largest: usize,
) -> Rounds {
    let mut peer = Command::new("python3")
        .arg(script)
        .arg(input)
        .arg(out)
        .arg("serve")
        .arg(largest.to_string())
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .spawn()
        .expect("python3 runs");
    let mut ask = peer.stdin.take().expect("the peer's input is piped");
    let mut answers = BufReader::new(peer.stdout.take().expect("the peer's output is piped"));
    let mut meshlab_run = || {
        writeln!(ask, "run").expect("the peer reads its input");
        let mut line = String::new();
        answers.read_line(&mut line).expect("the peer answers");
        line.trim()
            .parse::<f64>()
            .unwrap_or_else(|_| panic!("MeshLab's time, not {line:?}"))
    };
    let read_run = || {
        let read = read_obj(input);
        let start = Instant::now();
        fill_holes_in(read, options).expect("filled");
        start.elapsed().as_secs_f64() * 1e3
    };
    let in_place_run = || {
        let copy = mesh.clone();
        let start = Instant::now();
        fill_holes_in(copy, options).expect("filled");
        start.elapsed().as_secs_f64() * 1e3
    };
    let copy_run = || {
        let start = Instant::now();
        fill_holes(mesh, options).expect("filled");
        start.elapsed().as_secs_f64() * 1e3
    };
    let mut rounds = Rounds {
        after_read: Vec::new(),
        in_place: Vec::new(),
        copy: Vec::new(),
        meshlab: Vec::new(),
    };
    for _ in 0..ROUNDS {
        rounds.meshlab.push(meshlab_run());
        rounds.after_read.push(read_run());
        rounds.copy.push(copy_run());
        rounds.in_place.push(in_place_run());
    }
    drop(ask);
    let status = peer.wait().expect("the peer ends");
    assert!(status.success(), "MeshLab's script failed");
    rounds
}
