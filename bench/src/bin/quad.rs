//! Quad meshing (issue 18) of plane regions: quality and time per region, each mesh
//! written as OBJ to the temporary folder for a look.
//!
//! `cargo run -p dieface-bench --release --bin quad`

#[path = "../../../tests/common/quad_shapes.rs"]
mod shapes;

use dieface::geom::mesh::quad::quality::mesh_quality;
use dieface::geom::mesh::quad::{quad_mesh_region, QuadOptions, Region};
use dieface_bench::{median_time, write_obj};

fn main() {
    let dir = std::env::temp_dir().join("dieface-bench-quad");
    std::fs::create_dir_all(&dir).expect("a temporary folder");
    let cases: Vec<(&str, Region, f64)> = vec![
        ("square", shapes::square(), 10.0),
        ("disc", shapes::disc(), 5.0),
        ("ell", shapes::ell(), 8.0),
        ("plate_with_hole", shapes::plate_with_hole(), 8.0),
        ("door_inner", shapes::door_inner(), 20.0),
    ];
    println!("| region | size | quads | triangles | min / mean scaled Jacobian | angles | max aspect | inverted | time |");
    println!("|---|---:|---:|---:|---:|---:|---:|---:|---:|");
    for (name, region, size) in cases {
        let options = QuadOptions::at_size(size);
        let meshed = quad_mesh_region(&region, &options).expect("meshed");
        let time = median_time(
            || {
                quad_mesh_region(&region, &options).expect("meshed");
            },
            1,
            5,
        );
        let mesh = meshed.flat().expect("a mesh");
        write_obj(&mesh, &dir.join(format!("{name}.obj")), "", 6);
        let q = mesh_quality(&mesh);
        println!(
            "| {name} | {size} | {} | {} | {:.3} / {:.3} | {:.1} to {:.1} deg | {:.2} | {} | {:.2} ms |",
            q.quads,
            q.triangles,
            q.min_scaled_jacobian,
            q.mean_scaled_jacobian,
            q.min_angle,
            q.max_angle,
            q.max_aspect,
            q.inverted,
            time.as_secs_f64() * 1e3
        );
    }
}
