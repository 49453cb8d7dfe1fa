//! Writes `examples/inner_panel/inner_panel.obj`: the hole-filling test panel
//! (`tests/common/panel.rs`) at 12 mm elements, cut along a seam at x = 740 into two
//! patches 0.02 mm apart, as an FE mesh from CAD arrives: 14 holes and a crack.
//!
//! `cargo run -p dieface-bench --release --bin inner_panel`

#[path = "../../../tests/common/panel.rs"]
mod panel;

use std::path::Path;

fn main() {
    let mesh = panel::panel_with_crack(12.0, &panel::standard_holes(), Some((740.0, 0.02)));
    let mut text = String::from(
        "# An inner panel's FE mesh as CAD hands it over: 1000 x 600 mm over a domed \
         surface with a ridge,\n# 14 holes, and a 0.02 mm crack where two patches were \
         exported apart (x = 740).\n# Written by `cargo run -p dieface-bench --release --bin inner_panel`.\n",
    );
    for p in mesh.positions() {
        text.push_str(&format!("v {:.6} {:.6} {:.6}\n", p.x, p.y, p.z));
    }
    for f in mesh.faces() {
        let i = f.indices();
        text.push_str(&format!("f {} {} {}\n", i[0] + 1, i[1] + 1, i[2] + 1));
    }
    let path =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../examples/inner_panel/inner_panel.obj");
    std::fs::create_dir_all(path.parent().expect("a folder")).expect("the folder made");
    std::fs::write(&path, text).expect("the OBJ written");
    println!(
        "wrote {} ({} nodes, {} triangles)",
        path.display(),
        mesh.vertex_count(),
        mesh.face_count()
    );
}
