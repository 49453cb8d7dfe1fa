//! The fender's die face meshed as one conforming quad shell (issue 18).
//!
//! `cargo build --release && cargo run -p dieface-bench --release --bin die_face [SIZE]`
//!
//! Evaluates `examples/fender/fender.die`, sews its die face (product, step draw,
//! binder) and meshes it with `quad_mesh_shell` at SIZE (default 5 mm), reporting each
//! face's elements and quality and the whole shell's conformity; then times the real
//! binary (`target/release/dieface`, or `$DIEFACE`) building
//! `examples/fender/fender_deck.die` at that size to a `.k` deck, three times, as a
//! designer runs it: the whole process, and the build's own last line.

use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Instant;

use dieface::eval::Engine;
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
    let faces = model.die_face.faces.clone();
    let shell = sew(faces, DIE_FACE_TOLERANCE).expect("the fender's die face sews");
    let mut options = SurfaceMeshOptions::at_size(size);
    options.quad.chord_tolerance = 0.3;
    let sizes = vec![size; shell.faces.len()];
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
    println!("| face | quads | triangles | min SJ | mean SJ |");
    println!("|---|---:|---:|---:|---:|");
    for (f, face) in shell.faces.iter().enumerate() {
        let mesh = meshed.mesh_of(&[f]).expect("a face's mesh");
        let q = mesh_quality(&mesh);
        println!(
            "| {} | {} | {} | {:.3} | {:.3} |",
            face.face.name, q.quads, q.triangles, q.min_scaled_jacobian, q.mean_scaled_jacobian
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
    if let Ok(n) = std::env::var("WORST") {
        worst_elements(&shell, &meshed, n.parse().unwrap_or(20));
    }
    let topo = whole.topology();
    println!(
        "free edges {}, non-manifold edges {}",
        topo.free_edges().len(),
        topo.non_manifold_edges().len()
    );
    deck_build_times(&root, size);
}

/// The binary under test: `$DIEFACE`, else this checkout's release build.
fn binary() -> PathBuf {
    if let Some(p) = std::env::var_os("DIEFACE") {
        return PathBuf::from(p);
    }
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../target/release/dieface")
}

/// `dieface build fender_deck.die -o fender.k` at `size`, three times: the whole
/// process's time and the build's own report.
fn deck_build_times(examples: &Path, size: f64) {
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
    let text = std::fs::read_to_string(examples.join("fender/fender_deck.die"))
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
