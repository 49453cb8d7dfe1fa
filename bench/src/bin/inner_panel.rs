//! Writes `examples/inner_panel/inner_panel.obj`: the hole-filling test panel
//! (`tests/common/panel.rs`) at 12 mm elements, cut along a seam at x = 740 into two
//! patches 0.02 mm apart, as an FE mesh from CAD arrives: 14 holes and a crack.
//!
//! `cargo run -p dieface-bench --release --bin inner_panel`

#[path = "../../../tests/common/panel.rs"]
mod panel;

use std::path::Path;

use dieface_bench::write_obj;

fn main() {
    let mesh = panel::panel_with_crack(12.0, &panel::standard_holes(), Some((740.0, 0.02)));
    let path =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../examples/inner_panel/inner_panel.obj");
    write_obj(
        &mesh,
        &path,
        "An inner panel's FE mesh as CAD hands it over: 1000 x 600 mm over a domed surface with a ridge,\n\
         14 holes, and a 0.02 mm crack where two patches were exported apart (x = 740).\n\
         Written by `cargo run -p dieface-bench --release --bin inner_panel`.",
        6,
    );
    println!(
        "wrote {} ({} nodes, {} triangles)",
        path.display(),
        mesh.vertex_count(),
        mesh.face_count()
    );
}
