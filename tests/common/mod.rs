//! Helpers shared by the integration tests.

#[allow(dead_code)] // only the tests that decode pictures use it
pub mod picture;

use std::path::{Path, PathBuf};

/// Every `.die` file under `dir` (relative to the crate root), recursively, sorted.
#[allow(dead_code)] // not every test crate that shares these helpers reads the corpus
pub fn die_files(dir: &str) -> Vec<PathBuf> {
    fn collect(dir: &Path, out: &mut Vec<PathBuf>) {
        let Ok(entries) = std::fs::read_dir(dir) else {
            return;
        };
        for e in entries.flatten() {
            let p = e.path();
            if p.is_dir() {
                collect(&p, out);
            } else if p.extension().is_some_and(|x| x == "die") {
                out.push(p);
            }
        }
    }
    let mut out = Vec::new();
    collect(&Path::new(env!("CARGO_MANIFEST_DIR")).join(dir), &mut out);
    out.sort();
    out
}

/// The temporary files (`*.tmp`) left in `dir`: a build or watch that was stopped, or
/// failed, must leave none.
#[allow(dead_code)] // not every test crate that shares these helpers writes files
pub fn temp_files(dir: &Path) -> Vec<String> {
    std::fs::read_dir(dir)
        .expect("list the folder")
        .flatten()
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .filter(|n| n.ends_with(".tmp"))
        .collect()
}

/// A fresh, empty folder for one test, `target/tmp/SUITE/NAME` (removed first if a
/// previous run left it).
#[allow(dead_code)] // not every test crate that shares these helpers writes files
pub fn fresh_dir(suite: &str, name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join(suite)
        .join(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("temp dir");
    dir
}

/// Runs the `dieface` binary in `dir` with `args`: its exit code, stdout and stderr.
#[allow(dead_code)] // not every test crate that shares these helpers runs the binary
pub fn run_dieface(dir: &Path, args: &[&str]) -> (Option<i32>, String, String) {
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_dieface"))
        .current_dir(dir)
        .args(args)
        .output()
        .expect("run dieface");
    (
        out.status.code(),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

/// A sheet of `nx` x `ny` cells over (s, t) in [0, 1]², placed by `at`, two triangles a
/// cell wound counter-clockwise in (s, t) (split along the cell's diagonal from (i, j)
/// to (i + 1, j + 1)).
#[allow(dead_code)] // only the mesh tests build sheets
pub fn grid_sheet(
    nx: usize,
    ny: usize,
    at: &dyn Fn(f64, f64) -> glam::DVec3,
) -> dieface::geom::mesh::Mesh {
    use dieface::geom::mesh::{Face, Mesh};
    let mut positions = Vec::new();
    for j in 0..=ny {
        for i in 0..=nx {
            positions.push(at(i as f64 / nx as f64, j as f64 / ny as f64));
        }
    }
    let id = |i: usize, j: usize| (j * (nx + 1) + i) as u32;
    let mut faces = Vec::new();
    for j in 0..ny {
        for i in 0..nx {
            faces.push(Face::triangle(id(i, j), id(i + 1, j), id(i + 1, j + 1)));
            faces.push(Face::triangle(id(i, j), id(i + 1, j + 1), id(i, j + 1)));
        }
    }
    Mesh::new(positions, faces).expect("a valid sheet")
}

/// The vertices and triangles of object `name` (an `o` line) of an OBJ file that
/// `dieface build` wrote: the file's vertices are numbered across objects, so each
/// triangle's corners are taken into the object's own list.
#[allow(dead_code)] // only the tests that read the OBJ back use it
pub fn obj_object(path: &Path, name: &str) -> (Vec<glam::DVec3>, Vec<[u32; 3]>) {
    let text = std::fs::read_to_string(path).expect("the OBJ");
    let (mut all, mut positions, mut faces) = (Vec::new(), Vec::new(), Vec::new());
    let mut inside = false;
    let mut taken = std::collections::BTreeMap::new();
    for line in text.lines() {
        let mut words = line.split_whitespace();
        match words.next() {
            Some("v") => {
                let c: Vec<f64> = words.map(|w| w.parse().expect("a number")).collect();
                all.push(glam::DVec3::new(c[0], c[1], c[2]));
            }
            Some("o") => inside = words.next() == Some(name),
            Some("f") if inside => {
                let mut corner = |w: &str| -> u32 {
                    let i: usize = w
                        .split('/')
                        .next()
                        .and_then(|s| s.parse().ok())
                        .expect("an index");
                    *taken.entry(i).or_insert_with(|| {
                        positions.push(all[i - 1]);
                        positions.len() as u32 - 1
                    })
                };
                let c: Vec<u32> = words.map(&mut corner).collect();
                faces.push([c[0], c[1], c[2]]);
            }
            _ => {}
        }
    }
    (positions, faces)
}

/// A product (a 200 mm panel with a 30 mm bump in the middle) over a larger plain plate
/// 20 mm below it, and an outline curve: small, so each run of the binary on it takes
/// well under a second.
#[allow(dead_code)] // the tests that run the binary on a small part use it
pub const BUMPED_PANEL: &str = r#"
units mm deg
let half = 100 mm
let net = [ [ (i * half, j * half, if i == 1 and j == 1 then 30 mm else 0 mm) for j in range(0, 3) ] for i in range(0, 3) ]
product panel = nurbs_surface(degree: (2, 2), points: net)
let plate = nurbs_surface(degree: (1, 1), points: [[(-50, -50, -20), (-50, 250, -20)], [(250, -50, -20), (250, 250, -20)]])
let outline = sketch(top) {
    from (0, 0)
    line to (200, 0)
    fillet 20
    line to (200, 200)
    close
}
"#;
