//! Sheet models built by hand and the checks every solid of one must pass, shared by
//! the sheet tests (thickness, junctions, the language block).

#![allow(dead_code)] // each test file uses its own subset

use dieface::geom::mesh::{crossings, Mesh, Topology};
use dieface::sheet::geometry::MidSurface;
use dieface::sheet::topology::{EdgeId, Flange, Sheet, VertexId};
use glam::DVec3;

/// The volume a closed, outward-facing triangle mesh encloses (divergence theorem).
pub fn volume(mesh: &Mesh) -> f64 {
    let p = mesh.positions();
    mesh.faces()
        .iter()
        .map(|f| {
            let i = f.indices();
            p[i[0] as usize].dot(p[i[1] as usize].cross(p[i[2] as usize])) / 6.0
        })
        .sum()
}

/// The mesh is closed and every edge's two triangles agree on orientation.
pub fn assert_closed_and_oriented(mesh: &Mesh) {
    let topology = Topology::build(mesh);
    assert!(
        topology.is_closed(),
        "free edges: {:?}",
        topology.free_edges()
    );
    assert!(topology.non_manifold_edges().is_empty());
    assert!(topology.inconsistent_edges().is_empty());
}

/// Closed, manifold, consistently oriented, not through itself, and each group (a face
/// of the solid) in one plane.
pub fn assert_sound(solid: &Mesh) {
    assert_closed_and_oriented(solid);
    assert!(crossings(solid).is_empty());
    let p = solid.positions();
    for g in solid.groups() {
        let f = solid.faces()[g.faces()[0].0 as usize].indices();
        let (a, b, c) = (p[f[0] as usize], p[f[1] as usize], p[f[2] as usize]);
        let n = (b - a).cross(c - a).normalize();
        for t in g.faces() {
            for &i in solid.faces()[t.0 as usize].indices() {
                let off = n.dot(p[i as usize] - a).abs();
                assert!(off < 1e-9, "{}: a corner {off} mm off its plane", g.name());
            }
        }
    }
}

/// The edge joining vertices `a` and `c`.
pub fn edge_between(sheet: &Sheet, a: VertexId, c: VertexId) -> EdgeId {
    let b = &sheet.brep;
    b.edges_at(a)
        .unwrap()
        .into_iter()
        .find(|&e| {
            let (p, m) = b.halves_of(e).unwrap();
            [b.vertex(p).unwrap(), b.vertex(m).unwrap()].contains(&c)
        })
        .expect("an edge between the two vertices")
}

/// Places a new flange's far corners: each at `far(base)`, `base` the point of the
/// corner it was swept from.
pub fn place_flange(
    sheet: &Sheet,
    mid: &mut MidSurface,
    flange: &Flange,
    far: impl Fn(DVec3) -> DVec3,
) {
    for (base, end) in flange.far_ends {
        let from = mid.point(base).expect("the flanged edge is placed");
        mid.place(sheet, end, far(from)).unwrap();
    }
}
