//! Quad meshing (issue 18) of plane regions side by side with gmsh, in one run: per
//! region, element counts, quality and time for dieface's `quad_mesh_region` and for
//! gmsh (Frontal-Delaunay for quads and Blossom recombination, through its Python
//! module), each mesh written as OBJ to the temporary folder for a look.
//!
//! `cargo run -p dieface-bench --release --bin quad` (gmsh's rows need
//! `pip install gmsh==4.15.2`; without it, only dieface's rows are printed)
//!
//! Both meshers get the same region at the same element size. The region goes to gmsh
//! as JSON (`bench/reference/gmsh_quad.py` says how it builds its geometry and which
//! options it meshes with); gmsh's mesh comes back as OBJ (its quads and triangles as
//! it gives them, none split), is read into a `Mesh` like ours and measured by the same
//! `mesh_quality`. Times are medians of 5: ours of `quad_mesh_region`, gmsh's of its
//! geometry build and `generate(2)`, timed inside Python. Prints markdown for
//! BENCHMARKS.md.

#[path = "../../../tests/common/quad_surfaces.rs"]
mod surfaces;

use surfaces::shapes;

use std::path::{Path, PathBuf};
use std::process::Command;

use dieface::geom::mesh::quad::quality::{mesh_quality, MeshQuality};
use dieface::geom::mesh::quad::surface::{quad_mesh_surface, SurfaceMeshOptions, SurfaceRegion};
use dieface::geom::mesh::quad::{quad_mesh_region, QuadOptions, Region};
use dieface::geom::NurbsSurface;
use dieface_bench::{median_time, read_obj, write_obj};
use glam::DVec2;

/// Runs per time; the median is reported (by both meshers).
const RUNS: usize = 5;

/// How to get gmsh's rows when they cannot be had.
const INSTALL: &str = "pip install gmsh==4.15.2 (for python3)";

/// One mesher's result on one region: quality and the median time (ms).
struct Row {
    quality: MeshQuality,
    ms: f64,
}

/// A loop as JSON: `[[x, y], ...]`, full precision (Rust's shortest round-trip form).
fn loop_json(points: &[DVec2]) -> String {
    let pairs: Vec<String> = points
        .iter()
        .map(|p| format!("[{:?}, {:?}]", p.x, p.y))
        .collect();
    format!("[{}]", pairs.join(", "))
}

/// The region and the element size as the gmsh script reads them:
/// `{"size": s, "outer": [[x, y], ...], "holes": [[[x, y], ...], ...]}`.
fn region_json(region: &Region, size: f64) -> String {
    let holes: Vec<String> = region.holes.iter().map(|h| loop_json(h)).collect();
    format!(
        "{{\"size\": {size:?}, \"outer\": {}, \"holes\": [{}]}}\n",
        loop_json(&region.outer),
        holes.join(", ")
    )
}

/// The number after `"key":` in a flat JSON object (the script's one line of output).
fn json_number(text: &str, key: &str) -> Option<f64> {
    let at = text.find(&format!("\"{key}\""))? + key.len() + 2;
    let rest = text[at..].trim_start().strip_prefix(':')?.trim_start();
    let end = rest
        .find(|c: char| !(c.is_ascii_digit() || matches!(c, '.' | '-' | '+' | 'e' | 'E')))
        .unwrap_or(rest.len());
    rest[..end].parse().ok()
}

/// Why gmsh's rows cannot be had (python3 or its gmsh module missing), or `None` when
/// they can.
fn gmsh_missing() -> Option<String> {
    match Command::new("python3")
        .args(["-c", "import gmsh; print(gmsh.__version__)"])
        .output()
    {
        Err(_) => Some(format!(
            "python3 not found: install Python 3, then {INSTALL}"
        )),
        Ok(out) if !out.status.success() => Some(format!("gmsh not found: {INSTALL}")),
        Ok(_) => None,
    }
}

/// gmsh's row on `region` at `size`: writes `name.json` to `dir`, runs the script,
/// reads back `name.gmsh.obj` and measures it as ours is measured.
fn gmsh_row(script: &Path, dir: &Path, name: &str, region: &Region, size: f64) -> Row {
    let input = dir.join(format!("{name}.json"));
    let output = dir.join(format!("{name}.gmsh.obj"));
    std::fs::write(&input, region_json(region, size)).expect("the region's JSON written");
    let result = Command::new("python3")
        .arg(script)
        .arg(&input)
        .arg(&output)
        .arg(RUNS.to_string())
        .output()
        .expect("python3 runs");
    assert!(
        result.status.success(),
        "gmsh on {name}: {}",
        String::from_utf8_lossy(&result.stderr)
    );
    let text = String::from_utf8_lossy(&result.stdout);
    let ms = json_number(&text, "ms").expect("gmsh's time");
    Row {
        quality: mesh_quality(&read_obj(&output)),
        ms,
    }
}

/// One table row: the region, the mesher, the size, the quality figures, the time and
/// the time as a multiple of ours (`ratio`, none on our own row).
fn print_row(region: &str, mesher: &str, size: f64, row: &Row, ratio: Option<f64>) {
    let ratio = ratio.map_or("".to_string(), |r| format!("{r:.1}x"));
    println!(
        "| {region} | {mesher} | {size} | {} | {:.2} ms | {ratio} |",
        quality_cells(&row.quality),
        row.ms
    );
}

fn main() {
    let dir = std::env::temp_dir().join("dieface-bench-quad");
    std::fs::create_dir_all(&dir).expect("a temporary folder");
    let script: PathBuf = Path::new(env!("CARGO_MANIFEST_DIR")).join("reference/gmsh_quad.py");
    let missing = gmsh_missing();
    if let Some(why) = &missing {
        println!("gmsh's rows left out: {why}\n");
    }
    let cases: Vec<(&str, Region, f64)> = vec![
        ("square", shapes::square(), 10.0),
        ("disc", shapes::disc(), 5.0),
        ("ell", shapes::ell(), 8.0),
        ("plate_with_hole", shapes::plate_with_hole(), 8.0),
        ("door_inner", shapes::door_inner(), 20.0),
    ];
    println!("| region | mesher | size | quads | triangles | min / mean scaled Jacobian | angles | max aspect | inverted | time (median of {RUNS}) | gmsh time / ours |");
    println!("|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|");
    for (name, region, size) in cases {
        let options = QuadOptions::at_size(size);
        let meshed = quad_mesh_region(&region, &options).expect("meshed");
        let time = median_time(
            || {
                quad_mesh_region(&region, &options).expect("meshed");
            },
            1,
            RUNS,
        );
        let mesh = meshed.flat().expect("a mesh");
        write_obj(&mesh, &dir.join(format!("{name}.obj")), "", 6);
        let ours = Row {
            quality: mesh_quality(&mesh),
            ms: time.as_secs_f64() * 1e3,
        };
        print_row(name, "dieface", size, &ours, None);
        if missing.is_none() {
            let theirs = gmsh_row(&script, &dir, name, &region, size);
            print_row(name, "gmsh", size, &theirs, Some(theirs.ms / ours.ms));
        }
    }
    surface_table(&dir);
}

/// The quality columns of a table row: quads, triangles, least and mean scaled
/// Jacobian, corner angles, largest aspect, inverted elements.
fn quality_cells(q: &MeshQuality) -> String {
    format!(
        "{} | {} | {:.3} / {:.3} | {:.1} to {:.1} deg | {:.2} | {}",
        q.quads,
        q.triangles,
        q.min_scaled_jacobian,
        q.mean_scaled_jacobian,
        q.min_angle,
        q.max_angle,
        q.max_aspect,
        q.inverted
    )
}

/// Trimmed surfaces (paper 004's cases on surfaces): ours only, as gmsh would need the
/// surfaces as CAD geometry; quality measured in 3-D by the same `mesh_quality`.
fn surface_table(dir: &Path) {
    let (door, door_region) = surfaces::door_inner_on_surface();
    let (vessel, vessel_region) = surfaces::vessel_end();
    let cylinder = surfaces::half_cylinder();
    let mut tight = SurfaceMeshOptions::at_size(20.0);
    tight.quad.chord_tolerance = 0.1;
    let cases: Vec<(&str, &NurbsSurface, SurfaceRegion, SurfaceMeshOptions)> = vec![
        (
            "door inner on a Coons patch",
            &door,
            door_region,
            SurfaceMeshOptions::at_size(20.0),
        ),
        (
            "vessel end, 5 nozzles",
            &vessel,
            vessel_region,
            SurfaceMeshOptions::at_size(15.0),
        ),
        (
            "half cylinder R 50, sag 0.1 mm",
            &cylinder,
            SurfaceRegion::default(),
            tight,
        ),
    ];
    println!();
    println!("| surface | size | plane | quads | triangles | min / mean scaled Jacobian | angles | max aspect | inverted | time (median of {RUNS}) |");
    println!("|---|---:|---|---:|---:|---:|---:|---:|---:|---:|");
    for (name, surface, region, options) in cases {
        let meshed = quad_mesh_surface(surface, &region, &options).expect("meshed");
        let time = median_time(
            || {
                quad_mesh_surface(surface, &region, &options).expect("meshed");
            },
            1,
            RUNS,
        );
        let file = name.split(' ').next().unwrap_or("surface");
        write_obj(
            &meshed.mesh,
            &dir.join(format!("surface_{file}.obj")),
            "",
            6,
        );
        println!(
            "| {name} | {} | {:?} | {} | {:.1} ms |",
            options.quad.size,
            meshed.plane,
            quality_cells(&mesh_quality(&meshed.mesh)),
            time.as_secs_f64() * 1e3
        );
    }
}
