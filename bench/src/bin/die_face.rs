//! The fender's die face meshed as one conforming quad shell (issue 18).
//!
//! `cargo build --release && cargo run -p dieface-bench --release --bin die_face [SIZE] [beads]`
//!
//! Evaluates `examples/fender/fender.die`, sews its die face (product, step draw,
//! binder; with `beads`, the two draw beads' skins set into the binder and meshed at
//! 6 mm) and meshes it with `quad_mesh_shell` at SIZE (default 5 mm), reporting each
//! face's elements and quality and the whole shell's conformity; then times the real
//! binary (`target/release/dieface`, or `$DIEFACE`) building
//! `examples/fender/fender_deck.die` (with `beads`, `fender_bead_deck.die`) at that
//! size to a `.k` deck, three times, as a designer runs it: the whole process, and the
//! build's own last line.

use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Instant;

use dieface::eval::Engine;
use dieface::geom::imprint::imprint;
use dieface::geom::mesh::quad::quality::{mesh_quality, scaled_jacobian};
use dieface::geom::mesh::quad::shell::{quad_mesh_shell, ShellMesh};
use dieface::geom::mesh::quad::surface::SurfaceMeshOptions;
use dieface::geom::sew::{sew, Shell, DIE_FACE_TOLERANCE};
use glam::DVec3;

fn main() {
    let size: f64 = std::env::args()
        .nth(1)
        .and_then(|s| s.parse().ok())
        .unwrap_or(5.0);
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../examples");
    let mut engine = Engine::new(Some(root.clone()));
    let outcome = engine
        .evaluate_path(&root.join("fender/fender.die"))
        .expect("the fender example is readable");
    assert!(outcome.diagnostics.is_empty(), "the fender example builds");
    let model = engine.die_model(&outcome);
    let beads = std::env::args().nth(2).is_some_and(|a| a == "beads");
    let faces = model.die_face.faces.clone();
    let t = Instant::now();
    let mut shell = sew(faces, DIE_FACE_TOLERANCE).expect("the fender's die face sews");
    let mut sizes = vec![size; shell.faces.len()];
    if beads {
        for bead in &model.die_face.beads {
            let done = imprint(&mut shell, bead.clone(), DIE_FACE_TOLERANCE)
                .expect("the fender's beads stand on its binder");
            sizes.extend(std::iter::repeat_n(size, done.split.len()));
            sizes.push(6.0);
        }
    }
    println!(
        "sewn{} in {:.0} ms",
        if beads { " and beads imprinted" } else { "" },
        t.elapsed().as_secs_f64() * 1e3
    );
    let mut options = SurfaceMeshOptions::at_size(size);
    options.quad.chord_tolerance = 0.3;
    let t = Instant::now();
    let meshed = quad_mesh_shell(&shell, &sizes, &options);
    let took = t.elapsed();
    let meshed = match meshed {
        Ok(m) => m,
        Err(e) => {
            eprintln!("failed: {e}");
            std::process::exit(1);
        }
    };
    let sag = chord_sag(&shell, &meshed, options.quad.chord_tolerance);
    println!("| face | quads | triangles | min SJ | mean SJ | sag at edge midpoints / centres |");
    println!("|---|---:|---:|---:|---:|---:|");
    for (f, face) in shell.faces.iter().enumerate() {
        let mesh = meshed.mesh_of(&[f]).expect("a face's mesh");
        let q = mesh_quality(&mesh);
        println!(
            "| {} | {} | {} | {:.3} | {:.3} | {:.3} / {:.3} mm |",
            face.face.name,
            q.quads,
            q.triangles,
            q.min_scaled_jacobian,
            q.mean_scaled_jacobian,
            sag[f].0,
            sag[f].1
        );
        if let Ok(dir) = std::env::var("DUMP") {
            std::fs::write(format!("{dir}/{f}.obj"), obj_text(&mesh)).ok();
        }
    }
    let whole = meshed.whole().expect("the whole mesh");
    let q = mesh_quality(&whole);
    println!(
        "\nwhole: {} nodes, {} quads, {} triangles, min/mean SJ {:.3}/{:.3}, meshed in {:.0} ms",
        whole.vertex_count(),
        q.quads,
        q.triangles,
        q.min_scaled_jacobian,
        q.mean_scaled_jacobian,
        took.as_secs_f64() * 1e3
    );
    let (edge_sag, centre_sag) = sag
        .iter()
        .fold((0.0f64, 0.0f64), |m, f| (m.0.max(f.0), m.1.max(f.1)));
    println!(
        "chord sag off the faces' surfaces: element edge midpoints {edge_sag:.3} mm, element centres {centre_sag:.3} mm at most (tolerance {} mm)",
        options.quad.chord_tolerance
    );
    if let Ok(n) = std::env::var("WORST") {
        worst_elements(&shell, &meshed, n.parse().unwrap_or(20));
    }
    let topo = whole.topology();
    println!(
        "free edges {}, non-manifold edges {}",
        topo.free_edges().len(),
        topo.non_manifold_edges().len()
    );
    deck_build_times(&root, size, beads);
}

/// The binary under test: `$DIEFACE`, else this checkout's release build.
fn binary() -> PathBuf {
    if let Some(p) = std::env::var_os("DIEFACE") {
        return PathBuf::from(p);
    }
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../target/release/dieface")
}

/// `dieface build fender_deck.die -o fender.k` (with `beads`, the bead deck) at
/// `size`, three times: the whole process's time and the build's own report.
fn deck_build_times(examples: &Path, size: f64, beads: bool) {
    let bin = binary();
    if !bin.is_file() {
        println!(
            "\n(no {}: `cargo build --release` first for the build times)",
            bin.display()
        );
        return;
    }
    let dir = std::env::temp_dir().join(format!("dieface-bench-die-face-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("a temporary folder");
    std::fs::copy(examples.join("fender/fender.die"), dir.join("fender.die")).expect("copy");
    let deck = if beads {
        "fender/fender_bead_deck.die"
    } else {
        "fender/fender_deck.die"
    };
    let text = std::fs::read_to_string(examples.join(deck))
        .expect("the deck example")
        .replace("param size = 10 mm", &format!("param size = {size} mm"))
        .replace(
            "param product_size = 10 mm",
            &format!("param product_size = {size} mm"),
        );
    std::fs::write(dir.join("deck.die"), text).expect("write");
    println!("\n| run | whole process | the build's report | deck |");
    println!("|---:|---:|---|---:|");
    for run in 1..=3 {
        let t = Instant::now();
        let out = Command::new(&bin)
            .arg("build")
            .arg(dir.join("deck.die"))
            .arg("-o")
            .arg(dir.join("fender.k"))
            .output()
            .expect("dieface runs");
        let wall = t.elapsed().as_secs_f64() * 1e3;
        let text = String::from_utf8_lossy(&out.stdout).to_string()
            + &String::from_utf8_lossy(&out.stderr);
        let report = text
            .lines()
            .find(|l| l.starts_with("built in"))
            .unwrap_or("(failed)")
            .to_string();
        let bytes = std::fs::metadata(dir.join("fender.k")).map_or(0, |m| m.len());
        println!(
            "| {run} | {wall:.0} ms | {report} | {:.1} MB |",
            bytes as f64 / 1e6
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// How far the elements stray from the surfaces they mesh, as a die engineer checks a
/// tool mesh: the largest distance from an element edge's midpoint, and from an
/// element's centre, to its face's surface (each node's foot found from the whole
/// surface, each midpoint's and centre's by Newton from its nodes' feet), per face.
/// With `SAG` set, each element whose centre sags more than `tolerance`, with its
/// sides and its nodes' parameters.
fn chord_sag(shell: &Shell, meshed: &ShellMesh, tolerance: f64) -> Vec<(f64, f64)> {
    use dieface::geom::inversion::{closest_point_on_surface, project_to_surface_near};
    use rayon::prelude::*;
    let per_face: Vec<(f64, f64)> = shell
        .faces
        .par_iter()
        .zip(&meshed.elements)
        .map(|(face, elements)| {
            let surface = face.face.surface();
            let mut feet = std::collections::HashMap::new();
            let (mut edge, mut centre) = (0.0f64, 0.0f64);
            for e in elements {
                let ids = e.indices();
                let uv: Vec<(f64, f64)> = ids
                    .iter()
                    .map(|&v| {
                        *feet.entry(v).or_insert_with(|| {
                            closest_point_on_surface(surface, meshed.positions[v as usize])
                                .map_or((f64::NAN, f64::NAN), |f| (f.u, f.v))
                        })
                    })
                    .collect();
                let off = |p: DVec3, guess: (f64, f64)| {
                    project_to_surface_near(surface, p, guess).map_or(0.0, |f| f.distance)
                };
                let n = ids.len();
                for i in 0..n {
                    let (a, b) = (ids[i] as usize, ids[(i + 1) % n] as usize);
                    let mid = 0.5 * (meshed.positions[a] + meshed.positions[b]);
                    let guess = (
                        0.5 * (uv[i].0 + uv[(i + 1) % n].0),
                        0.5 * (uv[i].1 + uv[(i + 1) % n].1),
                    );
                    edge = edge.max(off(mid, guess));
                }
                let c = ids
                    .iter()
                    .map(|&v| meshed.positions[v as usize])
                    .sum::<DVec3>()
                    / n as f64;
                let guess = (
                    uv.iter().map(|p| p.0).sum::<f64>() / n as f64,
                    uv.iter().map(|p| p.1).sum::<f64>() / n as f64,
                );
                let at_centre = off(c, guess);
                if std::env::var_os("SAG").is_some() && at_centre > tolerance {
                    let sides: Vec<String> = (0..n)
                        .map(|i| {
                            format!(
                                "{:.1}",
                                meshed.positions[ids[i] as usize]
                                    .distance(meshed.positions[ids[(i + 1) % n] as usize])
                            )
                        })
                        .collect();
                    eprintln!(
                        "{}: centre {at_centre:.3} mm at ({:.1}, {:.1}, {:.1}), sides {}, uv {:?}",
                        face.face.name,
                        c.x,
                        c.y,
                        c.z,
                        sides.join(" "),
                        uv
                    );
                }
                centre = centre.max(at_centre);
            }
            (edge, centre)
        })
        .collect();
    per_face
}

/// A mesh as OBJ text, for looking at a face's mesh.
fn obj_text(mesh: &dieface::geom::mesh::Mesh) -> String {
    let mut out = String::new();
    for p in mesh.positions() {
        out += &format!("v {} {} {}\n", p.x, p.y, p.z);
    }
    for f in mesh.faces() {
        let ids: Vec<String> = f.indices().iter().map(|i| (i + 1).to_string()).collect();
        out += &format!("f {}\n", ids.join(" "));
    }
    out
}

/// With `WORST=N`: the `N` worst elements of the shell and every triangle, each with
/// its face, place, scaled Jacobian, side lengths, how many of its nodes lie on a seam,
/// and the size of the elements round it (the mean side of each neighbour sharing a
/// node): where the mesh is poor, and whether the size jumps there.
fn worst_elements(shell: &Shell, meshed: &ShellMesh, n: usize) {
    let seam_nodes = shell.vertices.len()
        + meshed
            .edge_segments
            .iter()
            .map(|s| s.saturating_sub(1))
            .sum::<usize>();
    let mut all: Vec<(f64, usize, usize)> = Vec::new();
    let mut star: Vec<Vec<(usize, usize)>> = vec![Vec::new(); meshed.positions.len()];
    for (f, elements) in meshed.elements.iter().enumerate() {
        for (k, e) in elements.iter().enumerate() {
            let c: Vec<DVec3> = e
                .indices()
                .iter()
                .map(|&v| meshed.positions[v as usize])
                .collect();
            all.push((scaled_jacobian(&c), f, k));
            for &v in e.indices() {
                star[v as usize].push((f, k));
            }
        }
    }
    let sides = |f: usize, k: usize| -> Vec<f64> {
        let ids = meshed.elements[f][k].indices();
        (0..ids.len())
            .map(|i| {
                meshed.positions[ids[i] as usize]
                    .distance(meshed.positions[ids[(i + 1) % ids.len()] as usize])
            })
            .collect()
    };
    let mean = |v: &[f64]| v.iter().sum::<f64>() / v.len() as f64;
    let report = |sj: f64, f: usize, k: usize| {
        let ids = meshed.elements[f][k].indices();
        let centre = ids
            .iter()
            .map(|&v| meshed.positions[v as usize])
            .sum::<DVec3>()
            / ids.len() as f64;
        let on_seam = ids.iter().filter(|&&v| (v as usize) < seam_nodes).count();
        let own = sides(f, k);
        let round: Vec<f64> = ids
            .iter()
            .flat_map(|&v| star[v as usize].iter())
            .filter(|&&(g, j)| (g, j) != (f, k))
            .map(|&(g, j)| mean(&sides(g, j)))
            .collect();
        let (lo, hi) = round
            .iter()
            .fold((f64::INFINITY, 0.0f64), |(a, b), &x| (a.min(x), b.max(x)));
        let sides_text: Vec<String> = own.iter().map(|l| format!("{l:.1}")).collect();
        let k = ids.len();
        let angles: Vec<String> = (0..k)
            .map(|i| {
                let at = meshed.positions[ids[i] as usize];
                let a = meshed.positions[ids[(i + 1) % k] as usize] - at;
                let b = meshed.positions[ids[(i + k - 1) % k] as usize] - at;
                let seam = if (ids[i] as usize) < seam_nodes {
                    "s"
                } else {
                    ""
                };
                format!("{:.0}{seam}", a.angle_between(b).to_degrees())
            })
            .collect();
        println!(
            "| {} | {} | {sj:.3} | ({:.0}, {:.0}, {:.0}) | {} | {} | {on_seam}/{} | {lo:.1}-{hi:.1} |",
            shell.faces[f].face.name,
            if ids.len() == 4 { "quad" } else { "tri" },
            centre.x,
            centre.y,
            centre.z,
            sides_text.join(" "),
            angles.join(" "),
            ids.len(),
        );
    };
    all.sort_by(|a, b| a.0.total_cmp(&b.0));
    println!("\n| face | kind | SJ | centre | sides (mm) | angles (deg, s: seam node) | on seam | neighbours' size (mm) |");
    println!("|---|---|---:|---|---|---|---:|---|");
    for &(sj, f, k) in all.iter().take(n) {
        report(sj, f, k);
    }
    println!("\ntriangles:");
    for &(sj, f, k) in all
        .iter()
        .filter(|e| meshed.elements[e.1][e.2].indices().len() == 3)
    {
        report(sj, f, k);
    }
}
