//! Sewing faces into a shell: T-junctions split, coinciding edges shared in opposite
//! directions, small gaps closed within the tolerance and larger ones left open, a
//! trimmed face sewn to the patches around it.

use dieface::geom::arc::circle;
use dieface::geom::sew::{sew, Face, Shape, Shell};
use dieface::geom::{NurbsSurface, TrimmedSurface};
use glam::DVec3;

/// The bilinear patch of the plane z = `z` over [x0, x1] x [y0, y1].
fn flat(x0: f64, x1: f64, y0: f64, y1: f64, z: f64) -> NurbsSurface {
    let k = vec![0.0, 0.0, 1.0, 1.0];
    NurbsSurface::new(
        1,
        1,
        k.clone(),
        k,
        vec![
            vec![DVec3::new(x0, y0, z), DVec3::new(x0, y1, z)],
            vec![DVec3::new(x1, y0, z), DVec3::new(x1, y1, z)],
        ],
    )
    .unwrap()
}

fn patch(name: &str, s: NurbsSurface) -> Face {
    Face {
        name: name.into(),
        shape: Shape::Patch(s),
    }
}

fn free_length(shell: &Shell) -> f64 {
    shell
        .free_edges()
        .iter()
        .map(|&e| shell.edges[e].curve.length())
        .sum()
}

#[test]
fn a_t_junction_is_split_and_shared() {
    // One long patch below, two short ones on top of it: the long top edge is split at
    // the vertex where the two short ones meet.
    let shell = sew(
        vec![
            patch("below", flat(0.0, 200.0, 0.0, 100.0, 0.0)),
            patch("left", flat(0.0, 100.0, 100.0, 200.0, 0.0)),
            patch("right", flat(100.0, 200.0, 100.0, 200.0, 0.0)),
        ],
        0.01,
    )
    .unwrap();
    let uses = shell.edge_uses();
    assert_eq!(
        uses.iter().filter(|&&u| u == 2).count(),
        3,
        "three shared edges"
    );
    assert!(uses.iter().all(|&u| u == 1 || u == 2));
    // The free boundary is the outline of the 200 x 200 square.
    assert!((free_length(&shell) - 800.0).abs() < 1e-9);
    // Shared edges run opposite ways in their two faces.
    for e in 0..shell.edges.len() {
        let dirs: Vec<bool> = shell
            .faces
            .iter()
            .flat_map(|f| f.bound.iter().filter(|b| b.0 == e).map(|b| b.1))
            .collect();
        if dirs.len() == 2 {
            assert_ne!(dirs[0], dirs[1], "edge {e}");
        }
    }
}

#[test]
fn a_gap_within_the_tolerance_is_closed_and_a_larger_one_is_not() {
    for (gap, sewn) in [(0.005, true), (0.05, false)] {
        let shell = sew(
            vec![
                patch("a", flat(0.0, 100.0, 0.0, 100.0, 0.0)),
                patch("b", flat(100.0, 200.0, 0.0, 100.0, gap)),
            ],
            0.01,
        )
        .unwrap();
        let shared = shell.edge_uses().iter().filter(|&&u| u == 2).count();
        assert_eq!(shared == 1, sewn, "gap {gap}");
    }
}

#[test]
fn a_trimmed_face_is_sewn_to_the_ring_around_it() {
    // A disc trimmed out of a square plate, and four quarter-ring patches around it
    // whose inner edges are the circle's quarters: the disc's single closed edge is
    // split at the four ring vertices and shared piece by piece.
    let r = 40.0;
    let disc = TrimmedSurface::new(
        flat(-100.0, 100.0, -100.0, 100.0, 0.0),
        circle(DVec3::ZERO, DVec3::X, DVec3::Y, r).unwrap(),
        0.01,
    )
    .unwrap();
    let mut faces = vec![Face {
        name: "disc".into(),
        shape: Shape::Trimmed(disc),
    }];
    for q in 0..4 {
        let a0 = q as f64 * std::f64::consts::FRAC_PI_2;
        let inner = dieface::geom::arc::circular_arc(
            DVec3::ZERO,
            DVec3::X,
            DVec3::Y,
            r,
            a0,
            a0 + std::f64::consts::FRAC_PI_2,
        )
        .unwrap();
        let outer = dieface::geom::arc::circular_arc(
            DVec3::ZERO,
            DVec3::X,
            DVec3::Y,
            2.0 * r,
            a0,
            a0 + std::f64::consts::FRAC_PI_2,
        )
        .unwrap();
        let ring = dieface::geom::construct::ruled(&inner, &outer).unwrap();
        faces.push(patch(&format!("ring{q}"), ring));
    }
    let shell = sew(faces, 0.01).unwrap();
    let disc_bound = &shell.faces[0].bound;
    assert_eq!(disc_bound.len(), 4, "the outline is split in four");
    let uses = shell.edge_uses();
    assert!(disc_bound.iter().all(|&(e, _)| uses[e] == 2));
    // The ring patches face down (u round the circle, v outwards): they are turned so
    // the shell is oriented like the disc, every shared edge used both ways.
    assert!(!shell.faces[0].reversed);
    assert!(shell.faces[1..].iter().all(|f| f.reversed));
    for (e, &u) in uses.iter().enumerate() {
        if u == 2 {
            let dirs: Vec<bool> = shell
                .faces
                .iter()
                .flat_map(|f| f.bound.iter().filter(|b| b.0 == e).map(|b| b.1))
                .collect();
            assert_ne!(dirs[0], dirs[1], "edge {e}");
        }
    }
    // Free: the outer circle only (the ring's radial edges are shared).
    let expected = std::f64::consts::TAU * 2.0 * r;
    assert!((free_length(&shell) - expected).abs() < 1e-6 * expected);
    let area = shell.area();
    let exact = std::f64::consts::PI * (2.0 * r) * (2.0 * r);
    assert!((area - exact).abs() < 1e-8 * exact, "{area} vs {exact}");
}
