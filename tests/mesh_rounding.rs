//! Rolling-ball rounding on shell meshes (issue 16, paper 000), step by step. Step 1:
//! the chain of sharp edges through a picked node, followed both ways to the mesh's
//! boundary or back to the start (refused, naming the node, where it branches or the
//! mesh is not manifold and consistently oriented), and the base meshes beside it.
//! Step 2: each base mesh offset by R keeping its topology.

mod common;

use std::f64::consts::{FRAC_PI_2, PI, TAU};

use common::grid_sheet as sheet;
use dieface::geom::mesh::rounding::base::{base_meshes, BaseMeshes};
use dieface::geom::mesh::rounding::chain::{
    chain_through, nearest_sharp_node, sharp_edges, ChainError, SharpChain, DEFAULT_FEATURE_ANGLE,
};
use dieface::geom::mesh::rounding::chain_polyline;
use dieface::geom::mesh::rounding::contact::{ball_at, profile};
use dieface::geom::mesh::rounding::index::TriangleGrid;
use dieface::geom::mesh::rounding::offset::offset_faces;
use dieface::geom::mesh::rounding::radius::RadiusLaw;
use dieface::geom::mesh::rounding::round::{round_chain, Rounded};
use dieface::geom::mesh::rounding::spine::{base_triangles, offset_triangles, spine, Region};
use dieface::geom::mesh::{Face, FaceId, Mesh, Topology};
use glam::DVec3;

/// Sheets joined into one mesh, their shared nodes welded.
fn joined(sheets: &[Mesh]) -> Mesh {
    let mut all = sheets[0].clone();
    for s in &sheets[1..] {
        all.append(s).expect("appended");
    }
    all.weld(1e-9).expect("welded")
}

/// A plate 100 mm long folded along the x axis: 40 mm flat on y < 0, then 40 mm turned
/// up by `turn` from it (90 deg: an L; 60 deg: the legs 120 deg apart), 20 cells along
/// and 8 across each leg.
fn folded(turn: f64) -> Mesh {
    let flat = sheet(20, 8, &|s, t| DVec3::new(100.0 * s, -40.0 + 40.0 * t, 0.0));
    let up = DVec3::new(0.0, turn.cos(), turn.sin());
    let leg = sheet(20, 8, &|s, t| {
        DVec3::new(100.0 * s, 0.0, 0.0) + 40.0 * t * up
    });
    joined(&[flat, leg])
}

/// A fold sharper than the feature angle is a chain from one end of the plate to the
/// other through the picked node: 21 nodes, 100 mm, open, whatever the fold's angle
/// (legs at 90 and 120 deg, and a shallow 20 deg turn with θ lowered to 10 deg). A
/// fold shallower than θ has no sharp edge.
#[test]
fn a_fold_is_one_open_chain_end_to_end() {
    for (turn, theta) in [
        (FRAC_PI_2, DEFAULT_FEATURE_ANGLE),
        (PI / 3.0, DEFAULT_FEATURE_ANGLE),
        (20f64.to_radians(), 10f64.to_radians()),
    ] {
        let mesh = folded(turn);
        let topology = Topology::build(&mesh);
        let sharp = sharp_edges(&mesh, &topology, theta);
        let (start, d) = nearest_sharp_node(&mesh, &topology, &sharp, DVec3::new(52.0, 1.0, 1.0))
            .expect("a sharp node");
        assert!(d < 2.5, "{d}");
        let chain = chain_through(&mesh, &topology, &sharp, start, None).expect("a chain");
        assert!(!chain.closed);
        assert_eq!((chain.nodes.len(), chain.edges.len()), (21, 20));
        assert!((chain.length(&mesh) - 100.0).abs() < 1e-9);
        let ends = [chain.nodes[0], chain.nodes[20]].map(|v| mesh.position(v).unwrap().x);
        assert!(ends.contains(&0.0) && ends.contains(&100.0), "{ends:?}");
        assert!(chain
            .nodes
            .iter()
            .all(|&v| mesh.position(v).unwrap().y == 0.0));
    }
    let shallow = folded(20f64.to_radians());
    let topology = Topology::build(&shallow);
    let sharp = sharp_edges(&shallow, &topology, DEFAULT_FEATURE_ANGLE);
    assert!(
        sharp.iter().all(|&s| !s),
        "20 deg is under the 30 deg default"
    );
}

/// A capped cylinder's rim is a closed chain: from a node on it, round and back to the
/// node, 48 edges, its length the rim polygon's perimeter.
#[test]
fn a_capped_cylinders_rim_is_a_closed_chain() {
    let (r, n) = (15.0, 48);
    let side = sheet(n, 6, &|s, t| {
        DVec3::new(r * (TAU * s).cos(), r * (TAU * s).sin(), 30.0 * t)
    });
    // The cap as a fan of rings, wound to face up, seen from above counter-clockwise.
    let cap = sheet(n, 3, &|s, t| {
        let rho = r * (1.0 - t) + 1e-3 * t;
        DVec3::new(rho * (TAU * s).cos(), rho * (TAU * s).sin(), 30.0)
    });
    let mesh = joined(&[side, cap]);
    let topology = Topology::build(&mesh);
    let sharp = sharp_edges(&mesh, &topology, DEFAULT_FEATURE_ANGLE);
    let (start, _) =
        nearest_sharp_node(&mesh, &topology, &sharp, DVec3::new(r, 0.0, 30.0)).expect("a node");
    let chain = chain_through(&mesh, &topology, &sharp, start, None).expect("a chain");
    assert!(chain.closed);
    assert_eq!((chain.nodes.len(), chain.edges.len()), (n, n));
    let perimeter = 2.0 * n as f64 * r * (PI / n as f64).sin();
    assert!((chain.length(&mesh) - perimeter).abs() < 1e-9);
}

/// A cube's edge runs into corners where three sharp edges meet: refused there, naming
/// the corner, unless a direction to follow picks one of them within 60 deg; with
/// (1, 1, 0) the chain turns the first corner and is refused at the next, where no edge
/// runs that way.
#[test]
fn a_chain_that_branches_is_refused_at_the_branch() {
    let faces: [&dyn Fn(f64, f64) -> DVec3; 6] = [
        &|s, t| DVec3::new(10.0 * s, 10.0 * t, 0.0),
        &|s, t| DVec3::new(10.0 * t, 10.0 * s, 10.0),
        &|s, t| DVec3::new(10.0 * t, 0.0, 10.0 * s),
        &|s, t| DVec3::new(10.0 * s, 10.0, 10.0 * t),
        &|s, t| DVec3::new(0.0, 10.0 * s, 10.0 * t),
        &|s, t| DVec3::new(10.0, 10.0 * t, 10.0 * s),
    ];
    let sheets: Vec<Mesh> = faces.iter().map(|f| sheet(4, 4, f)).collect();
    let mesh = joined(&sheets);
    let topology = Topology::build(&mesh);
    assert!(topology.is_closed());
    let sharp = sharp_edges(&mesh, &topology, DEFAULT_FEATURE_ANGLE);
    let node_at = |p: DVec3| {
        (0..mesh.vertex_count() as u32)
            .find(|&i| mesh.positions()[i as usize].distance(p) < 1e-9)
            .expect("a node there")
    };
    // The top front edge, y = 0, z = 10.
    let start = dieface::geom::mesh::VertexId(node_at(DVec3::new(5.0, 0.0, 10.0)));
    let corners = [
        node_at(DVec3::new(0.0, 0.0, 10.0)),
        node_at(DVec3::new(10.0, 0.0, 10.0)),
    ];
    match chain_through(&mesh, &topology, &sharp, start, None) {
        Err(ChainError::Branch { node, edges: 3 }) => assert!(corners.contains(&node)),
        other => panic!("{other:?}"),
    }
    let follow = Some(DVec3::new(1.0, 1.0, 0.0));
    match chain_through(&mesh, &topology, &sharp, start, follow) {
        Err(ChainError::Branch { node, edges: 3 }) => {
            assert_eq!(
                node,
                node_at(DVec3::new(10.0, 10.0, 10.0)),
                "the second corner"
            )
        }
        other => panic!("{other:?}"),
    }
}

/// A fin on the fold (a third face on one of its edges) leaves the chain's two sides
/// undecided there: refused, naming a node of that edge.
#[test]
fn a_chain_on_a_non_manifold_edge_is_refused() {
    let mesh = folded(FRAC_PI_2);
    let (a, b) = (DVec3::new(50.0, 0.0, 0.0), DVec3::new(55.0, 0.0, 0.0));
    let ids: Vec<u32> = [a, b]
        .iter()
        .map(|p| {
            (0..mesh.vertex_count() as u32)
                .find(|&i| mesh.positions()[i as usize].distance(*p) < 1e-9)
                .expect("a fold node")
        })
        .collect();
    let mut positions = mesh.positions().to_vec();
    positions.push(DVec3::new(52.5, -10.0, 10.0));
    let mut faces = mesh.faces().to_vec();
    faces.push(Face::triangle(ids[0], ids[1], positions.len() as u32 - 1));
    let fin = Mesh::new(positions, faces).expect("a mesh");
    let topology = Topology::build(&fin);
    let sharp = sharp_edges(&fin, &topology, DEFAULT_FEATURE_ANGLE);
    let (start, _) =
        nearest_sharp_node(&fin, &topology, &sharp, DVec3::new(20.0, 0.0, 0.0)).expect("a node");
    match chain_through(&fin, &topology, &sharp, start, None) {
        Err(ChainError::NotManifold { node }) => assert!(ids.contains(&node), "{node}"),
        other => panic!("{other:?}"),
    }
}

/// The L fold turned by `turn` (see [`folded`]), its topology, the chain along its
/// fold (picked at its middle) and the base meshes of a ball of radius `r` on it.
fn fold_round(turn: f64, r: f64) -> (Mesh, Topology, SharpChain, BaseMeshes) {
    let mesh = folded(turn);
    let topology = Topology::build(&mesh);
    let sharp = sharp_edges(&mesh, &topology, DEFAULT_FEATURE_ANGLE);
    let (start, _) =
        nearest_sharp_node(&mesh, &topology, &sharp, DVec3::new(50.0, 0.0, 0.0)).expect("a node");
    let chain = chain_through(&mesh, &topology, &sharp, start, None).expect("a chain");
    let base = base_meshes(&mesh, &topology, &chain, r).expect("two base meshes");
    (mesh, topology, chain, base)
}

/// Step 1, the base meshes: on the L fold (legs 5 mm a cell) with a 5 mm ball, the
/// faces within 3R of the fold, split by it: the flat's faces on one side, the rising
/// leg's on the other, none on both, and none out of reach.
#[test]
fn the_base_meshes_are_the_faces_within_3r_on_each_side() {
    let r = 5.0;
    let (mesh, _, _, base) = fold_round(FRAC_PI_2, r);
    let corners = |f: FaceId| -> Vec<DVec3> {
        mesh.face(f)
            .unwrap()
            .vertices()
            .map(|v| mesh.position(v).unwrap())
            .collect()
    };
    let flat = |f: FaceId| corners(f).iter().all(|p| p.z == 0.0);
    let upright = |f: FaceId| corners(f).iter().all(|p| p.y.abs() < 1e-12);
    let (one, other) = if flat(base.left[0]) {
        (&base.left, &base.right)
    } else {
        (&base.right, &base.left)
    };
    assert!(one.iter().all(|&f| flat(f)) && other.iter().all(|&f| upright(f)));
    // 20 cells along; across, the cells with a corner within 15 mm: 3 rows of 5 mm plus
    // the one whose near corner is at 15 mm, two triangles a cell.
    for side in [one, other] {
        assert_eq!(side.len(), 20 * 4 * 2, "{}", side.len());
        for &f in side.iter() {
            let reach = corners(f)
                .iter()
                .map(|p| p.y.abs().max(p.z.abs()))
                .fold(f64::MAX, f64::min);
            assert!(reach <= 3.0 * r + 1e-9);
        }
    }
}

/// Step 2, the offset keeping topology: each base mesh of a fold offset by R lies on
/// its leg's plane moved R along the normal, exactly, its nodes on the fold included
/// (each side's offset uses its own faces only, so the crease is kept: the two offset
/// planes meet on the exact spine). Legs 90 and 120 deg apart; on the concave side of
/// the fold (the side the faces' normals point to) the ball rolls at +R.
#[test]
fn a_base_mesh_offset_keeps_its_planes() {
    for turn in [FRAC_PI_2, PI / 3.0] {
        let r = 5.0;
        let (mesh, topology, _, base) = fold_round(turn, r);
        for side in [&base.left, &base.right] {
            let offset = offset_faces(&mesh, &topology, side, r);
            assert!(offset.folded.is_empty(), "{:?}", offset.folded);
            let n = mesh.face_normal(side[0]).unwrap();
            let on = mesh
                .position(mesh.face(side[0]).unwrap().vertex(0).unwrap())
                .unwrap();
            for (v, q) in &offset.points {
                assert!((n.dot(*q - on) - r).abs() < 1e-9, "{v:?} {q}");
                // Moved straight along the normal: the node's own place in the plane.
                let p = mesh.position(*v).unwrap();
                assert!((q - p - r * n).length() < 1e-9);
            }
        }
    }
}

/// Step 2's filter: a cylinder of radius 4 mm offset 5 mm towards its axis (inwards,
/// against its outward normals) folds over itself: every node is marked; offset
/// outwards, or inwards by 3 mm, none is.
#[test]
fn an_offset_tighter_than_the_surface_is_marked_folded() {
    let r = 4.0;
    let mesh = sheet(32, 4, &|s, t| {
        DVec3::new(r * (TAU * s).cos(), r * (TAU * s).sin(), 10.0 * t)
    });
    let mesh = mesh.weld(1e-9).expect("welded");
    let topology = Topology::build(&mesh);
    let faces: Vec<FaceId> = (0..mesh.face_count() as u32).map(FaceId).collect();
    // The sheet's winding gives normals out of the cylinder.
    let n = mesh.face_normal(faces[0]).unwrap();
    let c = mesh
        .face(faces[0])
        .unwrap()
        .vertices()
        .map(|v| mesh.position(v).unwrap())
        .sum::<DVec3>()
        / 3.0;
    assert!(n.dot(DVec3::new(c.x, c.y, 0.0)) > 0.0, "outward normals");
    let inward_far = offset_faces(&mesh, &topology, &faces, -5.0);
    assert_eq!(inward_far.folded.len(), mesh.vertex_count());
    for d in [5.0, -3.0] {
        assert!(
            offset_faces(&mesh, &topology, &faces, d).folded.is_empty(),
            "{d}"
        );
    }
}

/// A crease that dies out inside the plate (a fold 60 deg up along y = 0 for x below
/// 50 mm, easing flat by x = 70 mm): its chain ends short of the boundary, the faces on
/// its two sides join round its end within reach, and the base meshes are refused.
#[test]
fn a_chain_ending_inside_the_mesh_has_no_two_sides() {
    let mesh = sheet(20, 16, &|s, t| {
        let (x, y) = (100.0 * s, -40.0 + 80.0 * t);
        let ease = ((70.0 - x) / 20.0).clamp(0.0, 1.0);
        DVec3::new(x, y, if y > 0.0 { y * 3f64.sqrt() * ease } else { 0.0 })
    });
    let topology = Topology::build(&mesh);
    let sharp = sharp_edges(&mesh, &topology, DEFAULT_FEATURE_ANGLE);
    let (start, _) =
        nearest_sharp_node(&mesh, &topology, &sharp, DVec3::new(20.0, 0.0, 0.0)).expect("a node");
    let chain = chain_through(&mesh, &topology, &sharp, start, None).expect("a chain");
    let end = chain
        .nodes
        .iter()
        .map(|&v| mesh.position(v).unwrap().x)
        .fold(0.0, f64::max);
    assert!(
        end > 40.0 && end < 100.0,
        "the crease ends inside, at x = {end}"
    );
    assert!(matches!(
        base_meshes(&mesh, &topology, &chain, 10.0),
        Err(dieface::geom::mesh::rounding::base::BaseError::NotSplit { .. })
    ));
}

/// Steps 3 to 5 on two planes at 90 deg and at 120 deg (the legs of a fold, the ball
/// in the corner their normals face, R 5 mm): the spine is where the offsets cross,
/// exactly the analytic fillet's axis, (x, R (cos τ - 1) / sin τ, R) for a turn τ; each
/// ball touches both legs at R in their faces; each profile is the exact arc, every
/// sampled point R from the axis, tangent to both legs at its contacts. The worst
/// radius error and contact normal angle are printed.
#[test]
fn the_round_of_a_fold_is_the_analytic_fillet() {
    let r = 5.0;
    for turn in [FRAC_PI_2, PI / 3.0] {
        let (mesh, topology, chain, base) = fold_round(turn, r);
        let offsets = [&base.left, &base.right].map(|side| offset_faces(&mesh, &topology, side, r));
        let tri = offsets.each_ref().map(|o| offset_triangles(&mesh, o));
        let bases = [&base.left, &base.right].map(|side| base_triangles(&mesh, side));
        let grids = bases.clone().map(TriangleGrid::new);
        let points = spine(
            &chain_polyline(&mesh, &chain),
            (&tri[0], &tri[1]),
            (&grids[0], &grids[1]),
            r,
        );
        let axis = |x: f64| DVec3::new(x, r * (turn.cos() - 1.0) / turn.sin(), r);
        assert!(points.len() >= 21, "{} spine points", points.len());
        let xs: Vec<f64> = points.iter().map(|p| p.x).collect();
        let rising = xs.windows(2).all(|w| w[0] < w[1]);
        let falling = xs.windows(2).all(|w| w[0] > w[1]);
        assert!(rising || falling, "ordered along the chain: {xs:?}");
        let (lo, hi) = (xs[0].min(xs[xs.len() - 1]), xs[0].max(xs[xs.len() - 1]));
        assert!(lo < 1e-9 && hi > 100.0 - 1e-9, "{lo} {hi}");
        let (mut radius_error, mut normal_angle, mut off_axis) = (0.0f64, 0.0f64, 0.0f64);
        let leg_normal = DVec3::new(0.0, -turn.sin(), turn.cos());
        for p in &points {
            off_axis = off_axis.max(p.distance(axis(p.x)));
            let ball = ball_at(*p, (&bases[0], &bases[1]), r).expect("a ball");
            assert!(ball
                .regions
                .iter()
                .all(|g| *g != Region::Face || ball.moved < 1e-9));
            for q in ball.contacts {
                radius_error = radius_error.max((q.distance(ball.centre) - r).abs());
                // The profile's normal at a contact against the leg's there.
                let toward = (ball.centre - q).normalize();
                let leg = if q.z.abs() < 1e-9 {
                    DVec3::Z
                } else {
                    leg_normal
                };
                normal_angle = normal_angle.max(toward.angle_between(leg).to_degrees());
            }
            let arc = profile(&ball).expect("a profile");
            for k in 0..=16 {
                let s = arc.point_at(k as f64 / 16.0);
                radius_error = radius_error.max((s.distance(axis(p.x)) - r).abs());
                assert!((s.x - p.x).abs() < 1e-9, "the profile lies across the axis");
            }
        }
        eprintln!(
            "fold turned {:.0} deg, R {r}: {} spine points {off_axis:.1e} mm off the fillet's axis, \
             radius error {radius_error:.1e} mm, contact normal angle {normal_angle:.1e} deg",
            turn.to_degrees(),
            points.len()
        );
        assert!(off_axis < 1e-9 && radius_error < 1e-9 && normal_angle < 1e-6);
    }
}

/// A boss of radius `a` standing 30 mm on a plate reaching 30 mm round it, `n` facets
/// round (6 rows on each), its topology and the chain round its foot.
fn boss_on_plate(a: f64, n: usize) -> (Mesh, Topology, SharpChain) {
    let plate = sheet(n, 6, &|s, t| {
        let rho = a + 30.0 * (1.0 - t);
        DVec3::new(rho * (TAU * s).cos(), rho * (TAU * s).sin(), 0.0)
    });
    let wall = sheet(n, 6, &|s, t| {
        DVec3::new(a * (TAU * s).cos(), a * (TAU * s).sin(), 30.0 * t)
    });
    let mesh = joined(&[plate, wall]);
    let topology = Topology::build(&mesh);
    let sharp = sharp_edges(&mesh, &topology, DEFAULT_FEATURE_ANGLE);
    let (start, _) =
        nearest_sharp_node(&mesh, &topology, &sharp, DVec3::new(a, 0.0, 0.0)).expect("a node");
    let chain = chain_through(&mesh, &topology, &sharp, start, None).expect("a chain");
    (mesh, topology, chain)
}

/// Steps 1 to 5 on a plane and a cylinder: a boss of radius 20 mm standing on a plate,
/// 96 facets round, the concave foot rounded at R 4 mm. The chain is the foot's closed
/// polygon; the analytic fillet is a torus, its axis (the spine) the circle of radius
/// a + R at height R. The facets put the spine within the wall's chord sag (a (1 -
/// cos(π/96)), scaled by the offset) of that circle; the balls touch both bases at R
/// exactly, each contact in a face tangent to it (one on a facet's edge between its two
/// faces' normals, within half the facet angle of the analytic normal); every profile
/// point lies within the same sag of the torus. The figures are printed.
#[test]
fn the_round_of_a_boss_on_a_plate_follows_the_torus() {
    let (a, r, n) = (20.0, 4.0, 96);
    let (mesh, topology, chain) = boss_on_plate(a, n);
    assert!(chain.closed && chain.edges.len() == n);
    let base = base_meshes(&mesh, &topology, &chain, r).expect("two base meshes");
    let offsets = [&base.left, &base.right].map(|side| offset_faces(&mesh, &topology, side, r));
    let tri = offsets.each_ref().map(|o| offset_triangles(&mesh, o));
    let bases = [&base.left, &base.right].map(|side| base_triangles(&mesh, side));
    let grids = bases.clone().map(TriangleGrid::new);
    let points = spine(
        &chain_polyline(&mesh, &chain),
        (&tri[0], &tri[1]),
        (&grids[0], &grids[1]),
        r,
    );
    assert!(points.len() >= n, "{} spine points", points.len());
    let sag = a * (1.0 - (PI / n as f64).cos());
    // Off the torus: the distance to its axis circle less R.
    let torus = |p: DVec3| {
        let rho = (p.x * p.x + p.y * p.y).sqrt();
        ((rho - (a + r)).powi(2) + (p.z - r).powi(2)).sqrt() - r
    };
    let (mut off_axis, mut radius_error, mut off_torus, mut tangent) =
        (0.0f64, 0.0f64, 0.0f64, 0.0f64);
    let (mut analytic_angle, mut on_edges) = (0.0f64, 0.0f64);
    for p in &points {
        let rho = (p.x * p.x + p.y * p.y).sqrt();
        off_axis = off_axis.max(((rho - (a + r)).powi(2) + (p.z - r).powi(2)).sqrt());
        let ball = ball_at(*p, (&bases[0], &bases[1]), r).expect("a ball");
        for ((q, side), region) in ball.contacts.iter().zip(&bases).zip(ball.regions) {
            radius_error = radius_error.max((q.distance(ball.centre) - r).abs());
            let toward = (ball.centre - *q).normalize();
            // Tangent to the base face the contact lies in: its normal along the
            // centre's direction.
            let face = side
                .iter()
                .min_by(|s, t| {
                    let d = |x: &[DVec3; 3]| {
                        dieface::geom::mesh::rounding::spine::nearest_on_triangle(*q, x)
                            .0
                            .distance(*q)
                    };
                    d(s).total_cmp(&d(t))
                })
                .unwrap();
            let normal = (face[1] - face[0]).cross(face[2] - face[0]).normalize();
            let off = toward.angle_between(normal).to_degrees();
            if region == Region::Face {
                tangent = tangent.max(off);
            } else {
                // On a facet's edge the ball's normal lies between its two faces'.
                on_edges = on_edges.max(off);
            }
            let exact = if q.z.abs() < 1e-9 {
                DVec3::Z
            } else {
                DVec3::new(q.x, q.y, 0.0).normalize()
            };
            analytic_angle = analytic_angle.max(toward.angle_between(exact).to_degrees());
        }
        let arc = profile(&ball).expect("a profile");
        for k in 0..=16 {
            off_torus = off_torus.max(torus(arc.point_at(k as f64 / 16.0)).abs());
        }
    }
    eprintln!(
        "boss R {a} on a plate, {n} facets (sag {sag:.3e} mm), round R {r}: {} spine points \
         {off_axis:.3e} mm off the torus's axis, ball radius error {radius_error:.1e} mm, \
         profiles {off_torus:.3e} mm off the torus, contacts in a face {tangent:.1e} deg off \
         its normal, on a facet edge up to {on_edges:.2} deg off a face's (half the facet \
         angle: {:.3}), {analytic_angle:.2} deg off the analytic normals",
        points.len(),
        180.0 / n as f64
    );
    assert!(radius_error < 1e-9 && tangent < 1e-5);
    assert!(on_edges <= 180.0 / n as f64 + 1e-9 && analytic_angle <= 180.0 / n as f64);
    let allowed = sag * (a + r) / a;
    assert!(off_axis <= allowed * 1.001 && off_torus <= allowed * 1.001 + 1e-9);
}

/// The rounded mesh's checks: manifold, consistently oriented, not through itself,
/// with as many boundary loops as `before` (no new free edge), and the largest turn
/// (deg) across an edge where a round face meets a cut face (the stitch).
fn assert_stitched(before: &Mesh, rounded: &Rounded) -> f64 {
    let mesh = &rounded.mesh;
    let topology = Topology::build(mesh);
    assert!(topology.non_manifold_edges().is_empty(), "manifold");
    assert!(
        topology.inconsistent_edges().is_empty(),
        "consistently oriented: {:?}",
        topology
            .inconsistent_edges()
            .iter()
            .map(|&e| topology
                .edge_vertices(e)
                .map(|v| mesh.positions()[v.index()]))
            .collect::<Vec<_>>()
    );
    assert!(
        dieface::geom::mesh::crossings(mesh).is_empty(),
        "not through itself"
    );
    let loops = |m: &Mesh| Topology::build(m).boundary_loops().loops.len();
    assert_eq!(loops(mesh), loops(before), "no new free edge");
    let first_round = mesh.face_count() - rounded.round_faces;
    let mut stitch = 0.0f64;
    for e in topology.edges() {
        let faces: Vec<_> = topology.edge_faces(e).collect();
        if let [f, g] = faces[..] {
            if (f.index() < first_round) != (g.index() < first_round) {
                let angle = topology.dihedral_angle(mesh, e).unwrap_or(0.0);
                stitch = stitch.max(angle.to_degrees());
            }
        }
    }
    stitch
}

/// The largest `off` over the nodes of the round's strip of `rounded`.
fn worst_round_node(rounded: &Rounded, off: &dyn Fn(DVec3) -> f64) -> f64 {
    let round = &rounded.mesh;
    let first_round = round.face_count() - rounded.round_faces;
    round.faces()[first_round..]
        .iter()
        .flat_map(|f| {
            f.indices()
                .iter()
                .map(|&i| off(round.positions()[i as usize]))
        })
        .fold(0.0, f64::max)
}

/// Steps 6 to 8 on the folds at 90 and 120 deg (R 5 mm, the round meshed within
/// 0.01 mm): the rounded mesh is sound and closed where the input was, every node of
/// the round's strip within the tolerance of the analytic fillet's cylinder and
/// between its trim lines, and the turn at the stitch no more than one row's turn of
/// the round itself (the 90 deg fold's trim lines fall on node rows; the 120 deg one's
/// cut nodes are moved onto them). Figures printed.
#[test]
fn a_rounded_fold_is_sound_and_on_its_fillet() {
    let r = 5.0;
    for turn in [FRAC_PI_2, PI / 3.0] {
        let (mesh, topology, chain, _) = fold_round(turn, r);
        let rounded =
            round_chain(&mesh, &topology, &chain, &RadiusLaw::constant(r), 0.01).expect("rounded");
        let stitch = assert_stitched(&mesh, &rounded);
        let axis_y = r * (turn.cos() - 1.0) / turn.sin();
        let round = &rounded.mesh;
        let off = worst_round_node(&rounded, &|p| {
            (((p.y - axis_y).powi(2) + (p.z - r).powi(2)).sqrt() - r).abs()
        });
        // The round's rows: each turning at most 15 deg and within 0.01 mm of its arc.
        let step = (PI / 12.0).min(2.0 * (1.0 - 0.01 / r).acos());
        let rows = (turn / step).ceil().max(2.0);
        eprintln!(
            "fold turned {:.0} deg rounded at R {r}: {} faces ({} in the round), nodes {off:.1e} mm \
             off the fillet, {stitch:.2} deg turn at the stitch (a row turns {:.2})",
            turn.to_degrees(),
            round.face_count(),
            rounded.round_faces,
            turn.to_degrees() / rows
        );
        assert!(off < 0.01, "{off}");
        assert!(stitch <= turn.to_degrees() / rows + 2.0, "{stitch}");
    }
}

/// The mesh's face groups survive the round: on the 120 deg fold with its flat and its
/// rising leg in groups of their own, every face the cut kept (whole or split) stays
/// in its leg's group, and the round's own faces join none.
#[test]
fn a_round_keeps_the_mesh_s_face_groups() {
    let r = 5.0;
    let (mesh, topology, chain, _) = fold_round(PI / 3.0, r);
    let flat = |m: &Mesh, f: FaceId| {
        m.face(f).is_some_and(|face| {
            face.vertices()
                .all(|v| m.positions()[v.index()].z.abs() < 1e-9)
        })
    };
    let (flats, legs): (Vec<FaceId>, Vec<FaceId>) = mesh.face_ids().partition(|&f| flat(&mesh, f));
    let grouped = mesh
        .clone()
        .with_group("flat", flats)
        .and_then(|m| m.with_group("leg", legs))
        .expect("two groups");
    let rounded =
        round_chain(&grouped, &topology, &chain, &RadiusLaw::constant(r), 0.01).expect("rounded");
    let round = &rounded.mesh;
    let kept = round.face_count() - rounded.round_faces;
    let in_flat = round.group("flat").expect("the flat's group").faces();
    let in_leg = round.group("leg").expect("the leg's group").faces();
    assert!(in_flat.iter().all(|&f| flat(round, f)));
    assert!(in_leg.iter().all(|&f| !flat(round, f)));
    assert_eq!(
        in_flat.len() + in_leg.len(),
        kept,
        "every kept face grouped"
    );
    assert!(
        in_flat.iter().chain(in_leg).all(|f| f.index() < kept),
        "the round's faces in no group"
    );
}

/// The boss's foot rounded (a closed chain round a faceted cylinder): the strip closes
/// on itself, the mesh stays sound, the round's nodes lie within the facets' sag and
/// the tolerance of the torus, and the turn at the stitch is within a row's turn (and
/// 2 deg) of the round's own.
#[test]
fn a_rounded_boss_closes_round_its_foot() {
    let (a, r, n) = (20.0, 4.0, 96);
    let (mesh, topology, chain) = boss_on_plate(a, n);
    let rounded =
        round_chain(&mesh, &topology, &chain, &RadiusLaw::constant(r), 0.01).expect("rounded");
    let stitch = assert_stitched(&mesh, &rounded);
    let round = &rounded.mesh;
    let off = worst_round_node(&rounded, &|p| {
        let rho = (p.x * p.x + p.y * p.y).sqrt();
        (((rho - (a + r)).powi(2) + (p.z - r).powi(2)).sqrt() - r).abs()
    });
    let sag = a * (1.0 - (PI / n as f64).cos());
    eprintln!(
        "boss R {a} rounded at R {r}: {} faces ({} in the round), nodes {off:.2e} mm off the \
         torus (facet sag {sag:.2e}), {stitch:.2} deg turn at the stitch",
        round.face_count(),
        rounded.round_faces
    );
    assert!(off < sag * (a + r) / a + 0.01, "{off}");
    let step = (PI / 12.0).min(2.0 * (1.0 - 0.01 / r).acos()).to_degrees();
    assert!(stitch <= step + 2.0, "{stitch}");
}

/// The fold's faces turned over (normals away from the inner corner: the edge now
/// convex, a punch's shoulder seen from its outside) round the same corner: the ball
/// rolls against the normals, and the fillet is the same cylinder.
#[test]
fn a_convex_edge_is_rounded_against_its_normals() {
    let r = 5.0;
    let mesh = folded(FRAC_PI_2);
    let turned: Vec<Face> = mesh.faces().iter().map(|f| f.reversed()).collect();
    let mesh = Mesh::new(mesh.positions().to_vec(), turned).expect("a mesh");
    let topology = Topology::build(&mesh);
    let sharp = sharp_edges(&mesh, &topology, DEFAULT_FEATURE_ANGLE);
    let (start, _) =
        nearest_sharp_node(&mesh, &topology, &sharp, DVec3::new(50.0, 0.0, 0.0)).expect("a node");
    let chain = chain_through(&mesh, &topology, &sharp, start, None).expect("a chain");
    let edge = chain.edges[0];
    assert!(
        topology.signed_dihedral_angle(&mesh, edge).unwrap() > 0.0,
        "convex"
    );
    let rounded =
        round_chain(&mesh, &topology, &chain, &RadiusLaw::constant(r), 0.01).expect("rounded");
    assert_stitched(&mesh, &rounded);
    let off = worst_round_node(&rounded, &|p| {
        (((p.y + r).powi(2) + (p.z - r).powi(2)).sqrt() - r).abs()
    });
    assert!(off < 1e-9, "{off}");
}

/// The fold at 90 deg with its corner already rounded at `r0`: 40 mm flat, the round's
/// quarter circle in `rows` facets, then 40 mm up, 20 cells along x.
fn rounded_fold(r0: f64, rows: usize) -> Mesh {
    let flat = sheet(20, 8, &|s, t| {
        DVec3::new(100.0 * s, -40.0 + (40.0 - r0) * t, 0.0)
    });
    let round = sheet(20, rows, &|s, t| {
        let phi = FRAC_PI_2 * t;
        DVec3::new(100.0 * s, -r0 + r0 * phi.sin(), r0 - r0 * phi.cos())
    });
    let up = sheet(20, 8, &|s, t| {
        DVec3::new(100.0 * s, 0.0, r0 + (40.0 - r0) * t)
    });
    joined(&[flat, round, up])
}

/// The largest distance of a ball's centre from where the ball of the radius `law`
/// gives at its x (the chain running along x from 0) stands in the fold's corner,
/// (x, -r, r), and of its contacts from their feet on the two legs.
fn worst_corner_ball(rounded: &Rounded, law: &dyn Fn(f64) -> f64) -> f64 {
    rounded
        .balls
        .iter()
        .map(|b| {
            let r = law(b.centre.x);
            let at = DVec3::new(b.centre.x, -r, r);
            let feet = [DVec3::new(at.x, -r, 0.0), DVec3::new(at.x, 0.0, r)];
            let (c0, c1) = if b.contacts[0].z.abs() < 1e-9 {
                (b.contacts[0], b.contacts[1])
            } else {
                (b.contacts[1], b.contacts[0])
            };
            let radius = (b.radius - r).abs();
            b.centre
                .distance(at)
                .max(c0.distance(feet[0]))
                .max(c1.distance(feet[1]))
                .max(radius)
        })
        .fold(0.0, f64::max)
}

/// Step 5 with a variable radius on the fold at 90 deg: radii 4, 8 and 4 mm at x = 0,
/// 50 and 100 (a cubic spline between). Every ball stands in its plane across the
/// chain at the spline's radius there, touching both legs at their feet; the rounded
/// mesh is sound; each node of the round's strip lies within the tolerance (and the
/// loft's error between profiles, printed) of the circle of its x's radius.
#[test]
fn a_variable_radius_round_of_a_fold_follows_its_spline() {
    let (mesh, topology, chain, _) = fold_round(FRAC_PI_2, 6.0);
    let guide = chain_polyline(&mesh, &chain);
    // The chain may run either way along x: radii placed by their points.
    let along =
        |x: f64| dieface::geom::mesh::rounding::polyline_nearest(&guide, DVec3::new(x, 0.0, 0.0)).1;
    let law = RadiusLaw::through(
        &[(along(0.0), 4.0), (along(50.0), 8.0), (along(100.0), 4.0)],
        100.0,
        false,
    )
    .expect("positive radii");
    let rounded = round_chain(&mesh, &topology, &chain, &law, 0.01).expect("rounded");
    let at_x = |x: f64| law.at(along(x));
    let ball_error = worst_corner_ball(&rounded, &at_x);
    let stitch = assert_stitched(&mesh, &rounded);
    let off = worst_round_node(&rounded, &|p| {
        let r = at_x(p.x);
        (((p.y + r).powi(2) + (p.z - r).powi(2)).sqrt() - r).abs()
    });
    let radii: Vec<f64> = rounded.balls.iter().map(|b| b.radius).collect();
    let (lo, hi) = radii
        .iter()
        .fold((f64::INFINITY, 0.0f64), |(a, b), &r| (a.min(r), b.max(r)));
    eprintln!(
        "fold rounded at 4-8-4 mm: {} balls, radii {lo:.3}..{hi:.3} mm, ball error {ball_error:.1e} mm, \
         strip nodes {off:.1e} mm off their circles, stitch {stitch:.2} deg",
        rounded.balls.len()
    );
    assert!(ball_error < 1e-9, "{ball_error}");
    assert!(
        (lo - 4.0).abs() < 0.05 && (hi - 8.0).abs() < 0.05,
        "{lo} {hi}"
    );
    assert!(off < 0.02, "{off}");
    assert!(stitch < 15.0 + 2.0, "{stitch}");
}

/// Paper 000, section 4, on the fold whose corner was rounded at 7.5 mm in 6 facets:
/// the round through a node in its middle is its strip (its nodes off the rims, the 6
/// rows of faces), of radius 7.5 mm within 3 % (the facets' 15 deg read it 2 % tight), 100 mm long, with the flat and the leg
/// beside it; re-rounded at 15 mm, and at a radius rising from 7.5 to 15 mm and back,
/// the balls stand in the corner at their radius and the mesh stays sound.
#[test]
fn an_existing_round_is_found_and_widened() {
    use dieface::geom::mesh::curvature::node_curvatures;
    use dieface::geom::mesh::rounding::existing::{find_round, reround_site, DEFAULT_BAND};
    use dieface::geom::mesh::rounding::round::round_site;
    let r0 = 7.5;
    let mesh = rounded_fold(r0, 6);
    let topology = Topology::build(&mesh);
    let curvatures = node_curvatures(&mesh);
    let picked = (0..mesh.vertex_count())
        .min_by(|&a, &b| {
            let d = |i: usize| {
                mesh.positions()[i].distance(DVec3::new(
                    50.0,
                    -r0 + r0 * 0.5f64.sqrt(),
                    r0 - r0 * 0.5f64.sqrt(),
                ))
            };
            d(a).total_cmp(&d(b))
        })
        .expect("nodes");
    let found = find_round(
        &mesh,
        &topology,
        &|v| curvatures[v.index()],
        dieface::geom::mesh::VertexId(picked as u32),
        DEFAULT_BAND,
    )
    .expect("a round");
    eprintln!(
        "found round: radius {:.3} mm, {} nodes, {} faces, {:.1} mm long",
        found.radius,
        found.nodes.len(),
        found.faces.len(),
        found.length()
    );
    // A quadric through nodes 15 deg apart round a 7.5 mm arc reads it 2 % tighter.
    assert!((found.radius - r0).abs() < 0.03 * r0, "{}", found.radius);
    assert_eq!(found.nodes.len(), 21 * 5, "the nodes off the rims");
    assert_eq!(found.faces.len(), 20 * 6 * 2, "the strip's faces");
    assert!((found.length() - 100.0).abs() < 1e-9 && !found.closed && !found.convex);
    let guide = found.guide.clone();
    let along = |x: f64| {
        dieface::geom::mesh::rounding::polyline_nearest(&guide, DVec3::new(x, -3.0, 3.0)).1
    };
    let constant = RadiusLaw::constant(15.0);
    let peaked = RadiusLaw::through(
        &[(along(0.0), 7.5), (along(50.0), 15.0), (along(100.0), 7.5)],
        100.0,
        false,
    )
    .expect("positive radii");
    for (name, law) in [("15 mm", &constant), ("7.5-15-7.5 mm", &peaked)] {
        let site = reround_site(&mesh, &topology, &found, law.mean(100.0)).expect("two sides");
        let rounded = round_site(&mesh, &topology, &site, law, 0.01).expect("re-rounded");
        let at_x = |x: f64| law.at(along(x));
        let ball_error = worst_corner_ball(&rounded, &at_x);
        let stitch = assert_stitched(&mesh, &rounded);
        let off = worst_round_node(&rounded, &|p| {
            let r = at_x(p.x);
            (((p.y + r).powi(2) + (p.z - r).powi(2)).sqrt() - r).abs()
        });
        eprintln!(
            "re-rounded at {name}: {} balls, ball error {ball_error:.1e} mm, strip nodes \
             {off:.1e} mm off their circles, stitch {stitch:.2} deg, {} faces",
            rounded.balls.len(),
            rounded.mesh.face_count()
        );
        assert!(ball_error < 1e-9, "{ball_error}");
        assert!(off < 0.02, "{off}");
        // No face of the old round is left: every node off the new strip lies on a leg.
        let first_round = rounded.mesh.face_count() - rounded.round_faces;
        for f in &rounded.mesh.faces()[..first_round] {
            for &i in f.indices() {
                let p = rounded.mesh.positions()[i as usize];
                assert!(p.z.abs() < 1e-9 || p.y.abs() < 1e-9, "{p}");
            }
        }
    }
}

/// OpenCascade's fillets of the same sharp edges (`tests/data/fillet_reference.json`,
/// written by `tests/reference/fillet_reference.py`: each fold and the boss built as a
/// solid and its corner edge filleted by `BRepFilletAPI_MakeFillet`), sampled on their
/// fillet faces, against dieface's rounding surfaces of the tessellated edges. The
/// folds' faces are planes, so the two fillets are one cylinder: every sample on
/// dieface's surface to 1e-6 mm. The boss's 96 facets follow its cylinder within their
/// sag, and dieface's torus follows them: within the sag scaled out to the round
/// (`sag (a + r) / a`) and the round's tolerance. Figures printed.
#[test]
fn the_round_matches_opencascades_fillet() {
    use dieface::geom::inversion::closest_point_on_surface;
    let path =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/fillet_reference.json");
    let data: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(path).expect("the reference data"))
            .expect("JSON");
    let samples = |case: &str| -> Vec<DVec3> {
        data["cases"][case]["samples"]
            .as_array()
            .expect("samples")
            .iter()
            .map(|p| {
                let c: Vec<f64> = p
                    .as_array()
                    .expect("a point")
                    .iter()
                    .map(|x| x.as_f64().expect("a number"))
                    .collect();
                DVec3::new(c[0], c[1], c[2])
            })
            .collect()
    };
    let distances = |rounded: &Rounded, points: &[DVec3]| -> (f64, f64) {
        let d: Vec<f64> = points
            .iter()
            .map(|&p| {
                closest_point_on_surface(&rounded.surface, p)
                    .expect("a closest point")
                    .distance
            })
            .collect();
        (
            d.iter().copied().fold(0.0, f64::max),
            d.iter().sum::<f64>() / d.len() as f64,
        )
    };
    for (case, turn) in [("fold_90", FRAC_PI_2), ("fold_120", PI / 3.0)] {
        let r = data["cases"][case]["radius"].as_f64().expect("a radius");
        let (mesh, topology, chain, _) = fold_round(turn, r);
        let rounded =
            round_chain(&mesh, &topology, &chain, &RadiusLaw::constant(r), 0.01).expect("rounded");
        let points = samples(case);
        let (max, mean) = distances(&rounded, &points);
        eprintln!(
            "{case}: {} OpenCascade fillet samples, {max:.1e} mm from dieface's rounding \
             surface at most, {mean:.1e} mm on average",
            points.len()
        );
        assert!(max < 1e-6, "{case}: {max}");
    }
    let (a, r, n) = (20.0, 4.0, 96);
    assert_eq!(data["cases"]["boss"]["boss_radius"].as_f64(), Some(a));
    assert_eq!(data["cases"]["boss"]["radius"].as_f64(), Some(r));
    let (mesh, topology, chain) = boss_on_plate(a, n);
    let rounded =
        round_chain(&mesh, &topology, &chain, &RadiusLaw::constant(r), 0.01).expect("rounded");
    let points = samples("boss");
    let (max, mean) = distances(&rounded, &points);
    let sag = a * (1.0 - (PI / n as f64).cos());
    eprintln!(
        "boss: {} OpenCascade fillet samples, {max:.2e} mm from dieface's rounding surface at \
         most, {mean:.2e} mm on average (the facets' sag {sag:.2e} mm)",
        points.len()
    );
    assert!(max < sag * (a + r) / a + 0.01, "{max}");
}

/// A fold whose ends are cut slant (the mesh's boundary crossing the edge at 63 deg, not
/// square), so the spine's last balls stop short of the boundary: the round is carried
/// on past each end and trimmed where the boundary crosses it (paper 000, step 6). The
/// strip runs from boundary to boundary, its end nodes on the boundary's plane, and the
/// rounded mesh has the analytic area: the fillet cylinder between the slant planes is
/// as long as the fold at every angle.
#[test]
fn a_fold_cut_slant_is_rounded_to_its_ends() {
    let r = 5.0;
    let slant = 0.5;
    let flat = sheet(20, 8, &|s, t| {
        let y = -40.0 + 40.0 * t;
        DVec3::new(100.0 * s - slant * y, y, 0.0)
    });
    let leg = sheet(20, 8, &|s, t| DVec3::new(100.0 * s, 0.0, 40.0 * t));
    let mesh = joined(&[flat, leg]);
    let topology = Topology::build(&mesh);
    let sharp = sharp_edges(&mesh, &topology, DEFAULT_FEATURE_ANGLE);
    let (start, _) =
        nearest_sharp_node(&mesh, &topology, &sharp, DVec3::new(50.0, 0.0, 0.0)).expect("a node");
    let chain = chain_through(&mesh, &topology, &sharp, start, None).expect("a chain");
    let tolerance = 0.01;
    let rounded =
        round_chain(&mesh, &topology, &chain, &RadiusLaw::constant(r), tolerance).expect("rounded");
    let stitch = assert_stitched(&mesh, &rounded);
    let off = worst_round_node(&rounded, &|p| {
        (((p.y + r).powi(2) + (p.z - r).powi(2)).sqrt() - r).abs()
    });
    // The boundary's planes at the two ends: x + slant y = 0 and = 100.
    let past = worst_round_node(&rounded, &|p| {
        let c = p.x + slant * p.y;
        (-c).max(c - 100.0).max(0.0)
    });
    let round = &rounded.mesh;
    let first_round = round.face_count() - rounded.round_faces;
    let ends = round.faces()[first_round..]
        .iter()
        .flat_map(|f| f.indices().iter().map(|&i| round.positions()[i as usize]))
        .map(|p| p.x + slant * p.y)
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), c| {
            (lo.min(c), hi.max(c))
        });
    // A chord of the quarter circle spans R sin(h/2) 2 for R h of arc: the strip's area
    // falls short of the cylinder's by at most that ratio.
    let rows = (FRAC_PI_2 / (PI / 12.0)).ceil();
    let chord = (2.0 * r * (FRAC_PI_2 / rows / 2.0).sin() * rows) / (r * FRAC_PI_2);
    let exact = 2.0 * 100.0 * (40.0 - r) + 100.0 * r * FRAC_PI_2;
    let area = round.total_area();
    eprintln!(
        "slant fold at R {r}: {} balls, round strip from x + y/2 = {:.2e} to {:.6}, nodes \
         {off:.1e} mm off the fillet and {past:.1e} mm past the boundary, area {area:.4} \
         mm2 against {exact:.4} (chords {:.4} of the arc), stitch {stitch:.2} deg",
        rounded.balls.len(),
        ends.0,
        ends.1,
        chord
    );
    assert!(off < 1e-9, "{off}");
    assert!(past < 1e-9, "{past}");
    assert!(
        ends.0.abs() < 1e-9 && (ends.1 - 100.0).abs() < 1e-9,
        "{ends:?}"
    );
    let short = exact - area;
    assert!(
        short >= -1e-6 && short <= (1.0 - chord) * 100.0 * r * FRAC_PI_2 + 1e-6,
        "{area} {exact}"
    );
    assert!(stitch < 4.0, "{stitch}");
}

/// Step 7 alone on a plate 100 mm square in 10 mm cells, the guide along its edge y = 0
/// and the trim line at `line(x)`: the cut keeps exactly the plate's part beyond the
/// line (its area the integral), splits the faces the line crosses (none thrown away
/// whole that had a node outside), snaps the nodes lying within a fifth of an edge of
/// it, and puts every node of the cut on the line, in order along the guide; the kept
/// mesh is manifold, consistently wound, and its smallest angle is printed.
#[test]
fn the_cut_follows_the_trim_line_through_the_faces() {
    use dieface::geom::mesh::rounding::cut::cut_to_trim_lines;
    use dieface::geom::mesh::rounding::index::PolylineIndex;
    use dieface::geom::mesh::rounding::round::RoundSite;
    let plate = sheet(10, 10, &|s, t| DVec3::new(100.0 * s, 100.0 * t, 0.0));
    let topology = Topology::build(&plate);
    let guide = vec![DVec3::ZERO, DVec3::new(100.0, 0.0, 0.0)];
    let site = RoundSite {
        base: BaseMeshes {
            left: plate.face_ids().collect(),
            right: Vec::new(),
        },
        guide: guide.clone(),
        closed: false,
        convex: false,
        replaced: Vec::new(),
    };
    let index = PolylineIndex::new(&guide);
    type Line<'a> = &'a dyn Fn(f64) -> f64;
    let cases: [(&str, Line, f64); 3] = [
        ("between rows, at y = 23.7", &|_| 23.7, 100.0 * 76.3),
        ("just past a row, at y = 20.5", &|_| 20.5, 100.0 * 79.5),
        (
            "slant, y = 21 + 0.13 x",
            &|x| 21.0 + 0.13 * x,
            100.0 * (79.0 - 6.5),
        ),
    ];
    for (name, line, area) in cases {
        let trim: Vec<DVec3> = (0..=200)
            .map(|k| {
                let x = k as f64 / 2.0;
                DVec3::new(x, line(x), 0.0)
            })
            .collect();
        let cut = cut_to_trim_lines(&plate, &topology, &site, &index, &[trim, Vec::new()]);
        let faces: Vec<Face> = cut
            .faces
            .iter()
            .map(|t| Face::triangle(t[0], t[1], t[2]))
            .collect();
        let kept = Mesh::new(cut.positions.clone(), faces).expect("a mesh");
        let kept_topology = Topology::build(&kept);
        assert!(kept_topology.non_manifold_edges().is_empty(), "{name}");
        assert!(kept_topology.inconsistent_edges().is_empty(), "{name}");
        let smallest = kept
            .face_ids()
            .filter_map(|f| kept.face(f))
            .map(|f| {
                let p: Vec<DVec3> = f.vertices().map(|v| kept.positions()[v.index()]).collect();
                (0..3)
                    .map(|k| {
                        (p[(k + 1) % 3] - p[k])
                            .angle_between(p[(k + 2) % 3] - p[k])
                            .to_degrees()
                    })
                    .fold(180.0, f64::min)
            })
            .fold(180.0, f64::min);
        let row = &cut.rows[0];
        let on_line = row
            .iter()
            .map(|&v| {
                let p = cut.positions[v as usize];
                (p.y - line(p.x)).abs()
            })
            .fold(0.0, f64::max);
        let beyond = kept
            .positions()
            .iter()
            .zip(0..)
            .filter(|(_, v)| {
                !kept_topology
                    .vertex_faces(dieface::geom::mesh::VertexId(*v))
                    .is_empty()
            })
            .map(|(p, _)| line(p.x) - p.y)
            .fold(f64::NEG_INFINITY, f64::max);
        eprintln!(
            "cut {name}: {} faces split, {} nodes snapped, area {:.9} against {area}, cut nodes \
             {on_line:.1e} mm off the line, smallest angle {smallest:.1} deg",
            cut.split_faces,
            cut.snapped_nodes,
            kept.total_area()
        );
        assert!((kept.total_area() - area).abs() < 1e-9 * area, "{name}");
        assert!(
            on_line < 1e-9 && beyond < 1e-9,
            "{name}: {on_line} {beyond}"
        );
        assert!(row
            .windows(2)
            .all(|w| { cut.positions[w[0] as usize].x < cut.positions[w[1] as usize].x }));
        assert!(row.len() >= 11 && cut.rows[1].is_empty(), "{name}");
        assert!(smallest > 5.0, "{name}: {smallest}");
    }
}
