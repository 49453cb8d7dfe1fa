//! The fender's whole die face meshed as one conforming shell (`die_face_mesh`, issue
//! 18), checked the way an FE engineer checks a die-face mesh before a forming run:
//! the parts merged on their nodes' exact coordinates must be one manifold shell whose
//! only free edges run round the binder's outer edge; the product outline and the
//! punch opening must be element edges carrying the same nodes on both sides; no
//! node may be doubled; no element inverted.

use std::collections::{BTreeMap, BTreeSet};
use std::path::PathBuf;
use std::sync::Arc;

use dieface::die::model::{DieModel, Part, Shape};
use dieface::eval::Engine;
use dieface::geom::mesh::quad::quality::mesh_quality;
use dieface::geom::mesh::Mesh;
use dieface::geom::sew::{sew, DIE_FACE_TOLERANCE};
use glam::DVec3;

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("examples")
}

/// The fender deck example's model with its element sizes set (the script and the
/// fender it imports copied to a folder of their own).
fn deck_model(size: &str, product_size: &str) -> DieModel {
    deck_model_of("fender_deck.die", size, product_size)
}

/// The deck example `file` (in `examples/fender`) evaluated with its element sizes set.
fn deck_model_of(file: &str, size: &str, product_size: &str) -> DieModel {
    let text = std::fs::read_to_string(root().join("fender").join(file))
        .expect("the example reads")
        .replace("param size = 10 mm", &format!("param size = {size}"))
        .replace(
            "param product_size = 10 mm",
            &format!("param product_size = {product_size}"),
        );
    // A folder per call: the tests run side by side.
    static CALLS: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(0);
    let call = CALLS.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
    let dir = std::env::temp_dir().join(format!(
        "dieface-die-face-mesh-{}-{call}",
        std::process::id()
    ));
    std::fs::create_dir_all(&dir).expect("a temporary folder");
    std::fs::copy(root().join("fender/fender.die"), dir.join("fender.die")).expect("copy");
    std::fs::write(dir.join("deck.die"), text).expect("write the copy");
    let mut engine = Engine::new(Some(dir.clone()));
    let outcome = engine.evaluate_path(&dir.join("deck.die"));
    let _ = std::fs::remove_dir_all(&dir);
    let outcome = outcome.expect("the copy reads");
    assert!(
        outcome.diagnostics.is_empty(),
        "the deck example evaluates cleanly: {:?}",
        outcome.diagnostics.first().map(|d| &d.message)
    );
    engine.die_model(&outcome)
}

/// The meshes of the `die_mesh` declaration's parts, by their piece name.
fn feature_meshes(model: &DieModel) -> BTreeMap<String, Arc<Mesh>> {
    let part: &Part = model
        .parts
        .iter()
        .find(|p| p.name == "die_mesh")
        .expect("a die_mesh part");
    part.children
        .iter()
        .filter_map(|c| match &c.shape {
            Some(Shape::Mesh(m)) => Some((c.name.clone(), m.clone())),
            _ => None,
        })
        .collect()
}

type Key = [u64; 3];

/// An edge's elements: the part each belongs to and whether it runs the edge forward.
type Users = Vec<(String, bool)>;

fn key(p: DVec3) -> Key {
    [p.x.to_bits(), p.y.to_bits(), p.z.to_bits()]
}

/// Every element of every mesh as node keys.
fn elements(meshes: &BTreeMap<String, Arc<Mesh>>) -> Vec<(String, Vec<Key>)> {
    let mut out = Vec::new();
    for (name, m) in meshes {
        for f in m.faces() {
            let ids: Vec<Key> = f
                .indices()
                .iter()
                .map(|&v| key(m.positions()[v as usize]))
                .collect();
            out.push((name.clone(), ids));
        }
    }
    out
}

/// How many elements use each undirected edge, and in which direction each part uses
/// it.
fn edge_uses(elements: &[(String, Vec<Key>)]) -> BTreeMap<(Key, Key), Vec<(String, bool)>> {
    let mut uses: BTreeMap<(Key, Key), Vec<(String, bool)>> = BTreeMap::new();
    for (name, e) in elements {
        for i in 0..e.len() {
            let (a, b) = (e[i], e[(i + 1) % e.len()]);
            let forward = a < b;
            let k = if forward { (a, b) } else { (b, a) };
            uses.entry(k).or_default().push((name.clone(), forward));
        }
    }
    uses
}

/// Manifold and oriented: no edge has three elements, and the two elements of a
/// shared edge run it in opposite directions (across parts too).
fn check_manifold_and_oriented(uses: &BTreeMap<(Key, Key), Users>) {
    for (edge, users) in uses {
        assert!(
            users.len() <= 2,
            "edge at {:?} has {} elements",
            point(&edge.0),
            users.len()
        );
        if users.len() == 2 {
            assert_ne!(
                users[0].1,
                users[1].1,
                "edge at {:?} used the same way twice",
                point(&edge.0)
            );
        }
    }
}

fn point(k: &Key) -> DVec3 {
    DVec3::new(
        f64::from_bits(k[0]),
        f64::from_bits(k[1]),
        f64::from_bits(k[2]),
    )
}

#[test]
fn the_fender_die_face_mesh_is_one_conforming_shell_open_only_at_the_binder_edge() {
    let model = deck_model("25 mm", "25 mm");
    let meshes = feature_meshes(&model);
    let names: Vec<&str> = meshes.keys().map(String::as_str).collect();
    assert_eq!(
        names,
        ["die_mesh/binder", "die_mesh/product", "die_mesh/step_draw"],
        "one mesh per feature"
    );
    for (name, m) in &meshes {
        let q = mesh_quality(m);
        assert_eq!(q.inverted, 0, "{name}: no inverted element");
        // No element near folded. (The step draw's worst, where its radii's fine
        // elements meet the wall's coarse ones, is at 0.06 at 25 mm, 0.26 at 5 mm.)
        assert!(
            q.min_scaled_jacobian > 0.05,
            "{name}: least scaled Jacobian {}",
            q.min_scaled_jacobian
        );
        assert!(q.quad_share() > 0.97, "{name}: quads {}", q.quad_share());
    }
    let all = elements(&meshes);
    let uses = edge_uses(&all);
    check_manifold_and_oriented(&uses);
    // No node doubled: distinct nodes are at least a hundredth of a millimetre apart
    // (checked on a grid of 1 mm cells).
    let nodes: BTreeSet<Key> = all.iter().flat_map(|(_, e)| e.iter().copied()).collect();
    let mut cells: BTreeMap<[i64; 3], Vec<DVec3>> = BTreeMap::new();
    for k in &nodes {
        let p = point(k);
        cells
            .entry(p.floor().as_i64vec3().to_array())
            .or_default()
            .push(p);
    }
    for p in nodes.iter().map(point) {
        let c = p.floor().as_i64vec3();
        let mut near = 0;
        for dx in -1..=1 {
            for dy in -1..=1 {
                for dz in -1..=1 {
                    let cell = [c.x + dx, c.y + dy, c.z + dz];
                    near += cells
                        .get(&cell)
                        .map_or(0, |v| v.iter().filter(|q| q.distance(p) < 0.01).count());
                }
            }
        }
        assert_eq!(near, 1, "a second node within 0.01 mm of {p:?}");
    }
    // The free edges: all on the binder, forming one closed loop as long as the sewn
    // die face's own free boundary (its outer binder edge), every node of it on that
    // boundary.
    let free: Vec<(&(Key, Key), &Users)> = uses.iter().filter(|(_, u)| u.len() == 1).collect();
    assert!(
        free.iter().all(|(_, u)| u[0].0 == "die_mesh/binder"),
        "a free edge off the binder"
    );
    let mut degree: BTreeMap<Key, usize> = BTreeMap::new();
    for (e, _) in &free {
        *degree.entry(e.0).or_default() += 1;
        *degree.entry(e.1).or_default() += 1;
    }
    assert!(
        degree.values().all(|&d| d == 2),
        "the free edges form simple loops"
    );
    let mesh_length: f64 = free
        .iter()
        .map(|(e, _)| point(&e.0).distance(point(&e.1)))
        .sum();
    let mut engine = Engine::new(Some(root()));
    let fender = engine
        .evaluate_path(&root().join("fender/fender.die"))
        .expect("the fender reads");
    let faces = engine.die_model(&fender).die_face.faces;
    let shell = sew(faces, DIE_FACE_TOLERANCE).expect("the die face sews");
    let outer: f64 = shell
        .free_edges()
        .iter()
        .map(|&e| shell.edges[e].curve.length())
        .sum();
    assert!(
        mesh_length <= outer && mesh_length > outer * 0.999,
        "free edges {mesh_length} mm against the binder's outer edge {outer} mm"
    );
    let components = loops(&free.iter().map(|(e, _)| **e).collect::<Vec<_>>());
    assert_eq!(components, 1, "one free loop: the binder's outer edge");
}

/// How many closed loops the edges form.
fn loops(edges: &[(Key, Key)]) -> usize {
    let mut next: BTreeMap<Key, Vec<Key>> = BTreeMap::new();
    for (a, b) in edges {
        next.entry(*a).or_default().push(*b);
        next.entry(*b).or_default().push(*a);
    }
    let mut seen: BTreeSet<Key> = BTreeSet::new();
    let mut count = 0;
    for start in next.keys() {
        if seen.contains(start) {
            continue;
        }
        count += 1;
        let mut stack = vec![*start];
        while let Some(k) = stack.pop() {
            if seen.insert(k) {
                stack.extend(next[&k].iter().copied());
            }
        }
    }
    count
}

#[test]
fn the_product_outline_and_the_punch_opening_are_element_edges_on_both_sides() {
    let model = deck_model("25 mm", "25 mm");
    let meshes = feature_meshes(&model);
    let free_loop = |name: &str| -> BTreeSet<(Key, Key)> {
        let mut one = BTreeMap::new();
        one.insert(name.to_string(), meshes[name].clone());
        edge_uses(&elements(&one))
            .into_iter()
            .filter(|(_, u)| u.len() == 1)
            .map(|(e, _)| e)
            .collect()
    };
    let product = free_loop("die_mesh/product");
    let step = free_loop("die_mesh/step_draw");
    let binder = free_loop("die_mesh/binder");
    // The product's whole boundary (its outline) is edges of the step draw's boundary,
    // edge for edge: the same nodes on both sides, no T-junction.
    assert!(!product.is_empty());
    assert!(
        product.is_subset(&step),
        "an outline edge the step draw does not have"
    );
    // The step draw's other boundary (the punch opening) is edges of the binder.
    let opening: BTreeSet<(Key, Key)> = step.difference(&product).copied().collect();
    assert!(!opening.is_empty());
    assert!(
        opening.is_subset(&binder),
        "an opening edge the binder does not have"
    );
    assert_eq!(loops(&product.iter().copied().collect::<Vec<_>>()), 1);
    assert_eq!(loops(&opening.iter().copied().collect::<Vec<_>>()), 1);
}

#[test]
fn a_finer_product_size_refines_the_product_and_its_seam_only() {
    let model = deck_model("25 mm", "25 mm");
    let coarse = feature_meshes(&model);
    let fine = feature_meshes(&deck_model("25 mm", "12.5 mm"));
    let count = |m: &BTreeMap<String, Arc<Mesh>>, n: &str| m[n].face_count() as f64;
    let product = count(&fine, "die_mesh/product") / count(&coarse, "die_mesh/product");
    let binder = count(&fine, "die_mesh/binder") / count(&coarse, "die_mesh/binder");
    // Half the size: more than twice the elements on the product (at 25 mm the step
    // draw's bands already set its outline's nodes closer than 25 mm where a row curves
    // tightly in plan, so not the four times of a free seam); the binder keeps its size
    // (it only grades in from the finer opening line the bands' columns bring).
    assert!(
        (2.5..5.0).contains(&product),
        "product x{product}, binder x{binder}"
    );
    assert!(
        (0.9..1.4).contains(&binder),
        "product x{product}, binder x{binder}"
    );
}

#[test]
fn beads_set_into_the_binder_share_their_feet_with_it_and_leave_no_free_edge() {
    let model = deck_model_of("fender_bead_deck.die", "25 mm", "25 mm");
    let meshes = feature_meshes(&model);
    let names: Vec<&str> = meshes.keys().map(String::as_str).collect();
    assert_eq!(
        names,
        [
            "die_mesh/binder",
            "die_mesh/product",
            "die_mesh/rear_corner",
            "die_mesh/step_draw",
            "die_mesh/wheel_arch"
        ],
        "one mesh per feature, each bead its own"
    );
    for (name, m) in &meshes {
        let q = mesh_quality(m);
        eprintln!(
            "{name}: {} quads {} tris, min SJ {:.3}, mean {:.3}",
            q.quads, q.triangles, q.min_scaled_jacobian, q.mean_scaled_jacobian
        );
        assert_eq!(q.inverted, 0, "{name}: no inverted element");
        assert!(
            q.min_scaled_jacobian > 0.05,
            "{name}: least scaled Jacobian {}",
            q.min_scaled_jacobian
        );
        // The binder grades from the beads' 6 mm feet to 25 mm here, and leaves a
        // triangle pair now and then on the way (1 % at its own 10 mm).
        assert!(q.quad_share() > 0.9, "{name}: quads {}", q.quad_share());
    }
    let all = elements(&meshes);
    let uses = edge_uses(&all);
    check_manifold_and_oriented(&uses);
    // Still open only round the binder's outer edge: the beads' feet and ends are
    // all shared with the binder.
    let free: Vec<_> = uses.iter().filter(|(_, u)| u.len() == 1).collect();
    assert!(
        free.iter().all(|(_, u)| u[0].0 == "die_mesh/binder"),
        "a free edge off the binder"
    );
    assert_eq!(loops(&free.iter().map(|(e, _)| **e).collect::<Vec<_>>()), 1);
    for bead in ["die_mesh/wheel_arch", "die_mesh/rear_corner"] {
        // The bead's whole boundary is binder edges: one closed footprint each.
        let bead_edges: Vec<(Key, Key)> = uses
            .iter()
            .filter(|(_, u)| {
                u.len() == 2
                    && u.iter().any(|x| x.0 == bead)
                    && u.iter().any(|x| x.0 == "die_mesh/binder")
            })
            .map(|(e, _)| *e)
            .collect();
        assert!(!bead_edges.is_empty(), "{bead} meets the binder");
        assert_eq!(loops(&bead_edges), 1, "{bead}: one footprint");
        let own: usize = uses
            .iter()
            .filter(|(_, u)| u.len() == 1 && u[0].0 == bead)
            .count();
        assert_eq!(own, 0, "{bead}: no free edge");
    }
}

/// The distance from `p` (x, y) to a step draw's profile: a land along y = 0 to
/// x = 22, a die radius of 8 mm round (22, -8) down to (30, -8), a wall at x = 30.
fn off_die_radius(p: DVec3) -> f64 {
    let land = if p.x <= 22.0 {
        p.y.abs()
    } else {
        f64::INFINITY
    };
    let wall = if p.y <= -8.0 {
        (p.x - 30.0).abs()
    } else {
        f64::INFINITY
    };
    let c = glam::DVec2::new(22.0, -8.0);
    let d = glam::DVec2::new(p.x, p.y) - c;
    let radius = if d.x >= 0.0 && d.y >= 0.0 {
        (d.length() - 8.0).abs()
    } else {
        f64::INFINITY
    };
    land.min(wall).min(radius)
}

#[test]
fn a_die_radius_is_meshed_in_rows_whose_chords_sag_within_the_tolerance() {
    use dieface::geom::construct::ruled;
    use dieface::geom::mesh::quad::shell::quad_mesh_shell;
    use dieface::geom::mesh::quad::sizing::chord_for_sag;
    use dieface::geom::mesh::quad::surface::SurfaceMeshOptions;
    use dieface::geom::sew::{Face, Shape as FaceShape};
    use dieface::geom::sketch::{draw, Command};
    use dieface::geom::transform::Transform;
    use glam::DVec2;
    // A step draw's section (land, R 8 die radius, wall) run straight along z as two
    // patches side by side, sharing the section at z = 60.
    let profile = draw(&[
        Command::From(DVec2::new(0.0, 0.0)),
        Command::LineTo(DVec2::new(22.0, 0.0)),
        Command::TangentArcTo(DVec2::new(30.0, -8.0)),
        Command::LineTo(DVec2::new(30.0, -40.0)),
    ])
    .expect("the profile draws")
    .curve
    .to_3d();
    let at = |z: f64| {
        Transform::translate(DVec3::new(0.0, 0.0, z))
            .expect("a translation")
            .apply_curve(&profile)
    };
    let faces: Vec<Face> = [(0.0, 60.0), (60.0, 150.0)]
        .iter()
        .enumerate()
        .map(|(k, &(z0, z1))| Face {
            name: format!("step_draw/{k}"),
            shape: FaceShape::Patch(ruled(&at(z0), &at(z1)).expect("a ruled patch")),
        })
        .collect();
    let shell = sew(faces, DIE_FACE_TOLERANCE).expect("the patches sew");
    let (size, tolerance) = (10.0, 0.3);
    let mut options = SurfaceMeshOptions::at_size(size);
    options.quad.chord_tolerance = tolerance;
    let meshed = quad_mesh_shell(&shell, &[size, size], &options).expect("meshed");
    let whole = meshed.whole().expect("one mesh");
    let q = mesh_quality(&whole);
    assert_eq!((q.triangles, q.inverted), (0, 0));
    assert!(q.min_scaled_jacobian > 0.9, "{}", q.min_scaled_jacobian);
    // Conforming: no edge of three elements, and the shared section is no free edge.
    let topology = whole.topology();
    assert!(topology.non_manifold_edges().is_empty());
    for e in topology.free_edges() {
        let [a, b] = topology.edge_vertices(e);
        let (p, r) = (
            whole.positions()[a.0 as usize],
            whole.positions()[b.0 as usize],
        );
        assert!(
            (p.z - 60.0).abs() > 1e-6 || (r.z - 60.0).abs() > 1e-6,
            "a free edge on the shared section at {p:?}"
        );
    }
    // Every chord, and every element's centre, within the tolerance of the surface.
    let mut worst: f64 = 0.0;
    for f in whole.faces() {
        let ids = f.indices();
        let p: Vec<DVec3> = ids.iter().map(|&v| whole.positions()[v as usize]).collect();
        for i in 0..p.len() {
            worst = worst.max(off_die_radius(0.5 * (p[i] + p[(i + 1) % p.len()])));
        }
        worst = worst.max(off_die_radius(p.iter().sum::<DVec3>() / p.len() as f64));
    }
    assert!(worst <= tolerance, "a chord sags {worst} mm");
    // Meshed as a forming engineer meshes a die radius: rows along it, every node on
    // one of a few sections' worth of profile points, the rows across the radius no
    // further apart than its chord allows, the columns along it at the element size.
    let mut rows: Vec<(i64, i64)> = whole
        .positions()
        .iter()
        .map(|p| ((p.x * 1e6).round() as i64, (p.y * 1e6).round() as i64))
        .collect();
    rows.sort();
    rows.dedup();
    assert!(rows.len() < 30, "{} rows", rows.len());
    let across = chord_for_sag(8.0, tolerance);
    let mut longest_across: f64 = 0.0;
    for f in whole.faces() {
        let p: Vec<DVec3> = f
            .indices()
            .iter()
            .map(|&v| whole.positions()[v as usize])
            .collect();
        for i in 0..p.len() {
            let (a, b) = (p[i], p[(i + 1) % p.len()]);
            let in_radius = |p: DVec3| p.x > 22.0 - 1e-6 && p.y > -8.0 - 1e-6;
            if (a.z - b.z).abs() < 1e-9 && in_radius(a) && in_radius(b) {
                longest_across = longest_across.max(a.distance(b));
            }
        }
    }
    assert!(
        longest_across <= across,
        "{longest_across} mm across the radius"
    );
    assert!(
        whole.face_count() < 2 * 150 * 70 / 40,
        "{} elements",
        whole.face_count()
    );
}
