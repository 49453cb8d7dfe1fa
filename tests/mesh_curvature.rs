//! Curvature at mesh nodes from a least-squares quadric (issue 16, paper 000 section 4:
//! "on a tessellated cylinder, sphere and torus, the quadric curvatures within a few
//! per cent of the analytic ones (figures per mesh density)"). Each surface is
//! tessellated on a parameter grid at three densities; at every node the quadric's
//! principal curvatures are compared with the surface's own, and the worst relative
//! error is printed per density (`cargo test --test mesh_curvature -- --nocapture`).

use std::f64::consts::{PI, TAU};

use dieface::geom::mesh::curvature::{node_curvatures, NodeCurvature};
use dieface::geom::mesh::{Face, Mesh};
use glam::DVec3;

/// A mesh of `surface` over an `nu` x `nv` grid of parameters in [0, 1]², two
/// triangles per cell, closed round u when `closed_u` and round v when `closed_v`,
/// wound so its normals point along `outward` at each point.
fn grid_mesh(
    nu: usize,
    nv: usize,
    (closed_u, closed_v): (bool, bool),
    surface: &dyn Fn(f64, f64) -> DVec3,
    outward: &dyn Fn(f64, f64) -> DVec3,
) -> (Mesh, Vec<(f64, f64)>) {
    let rows = if closed_v { nv } else { nv + 1 };
    let columns = if closed_u { nu } else { nu + 1 };
    let mut positions = Vec::new();
    let mut params = Vec::new();
    for j in 0..rows {
        for i in 0..columns {
            let (u, v) = (i as f64 / nu as f64, j as f64 / nv as f64);
            positions.push(surface(u, v));
            params.push((u, v));
        }
    }
    let id = |i: usize, j: usize| ((j % rows) * columns + i % columns) as u32;
    let mut faces = Vec::new();
    for j in 0..nv {
        for i in 0..nu {
            let (a, b, c, d) = (id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1));
            faces.push([a, b, c]);
            faces.push([a, c, d]);
        }
    }
    // Wound so the first triangle faces out; every other is wound the same way.
    let [a, b, c] = faces[0].map(|k| positions[k as usize]);
    let (u, v) = params[faces[0][0] as usize];
    let flip = (b - a).cross(c - a).dot(outward(u, v)) < 0.0;
    let faces = faces
        .into_iter()
        .map(|[a, b, c]| {
            if flip {
                Face::triangle(a, c, b)
            } else {
                Face::triangle(a, b, c)
            }
        })
        .collect();
    (Mesh::new(positions, faces).expect("a valid mesh"), params)
}

/// The worst relative errors of the larger and the smaller principal curvature over
/// the nodes `keep` accepts, against `exact` (max, min) at each node's parameters;
/// an exact curvature of 0 is compared against `scale` instead.
fn worst_errors(
    mesh: &Mesh,
    params: &[(f64, f64)],
    keep: &dyn Fn(f64, f64) -> bool,
    exact: &dyn Fn(f64, f64) -> (f64, f64),
    scale: f64,
) -> (f64, f64, usize) {
    let found = node_curvatures(mesh);
    let (mut worst_max, mut worst_min, mut nodes) = (0.0f64, 0.0f64, 0);
    for (k, c) in found.iter().enumerate() {
        let (u, v) = params[k];
        if !keep(u, v) {
            continue;
        }
        let c: &NodeCurvature = c.as_ref().expect("a curvature at every node kept");
        let (max, min) = exact(u, v);
        let rel = |got: f64, want: f64| (got - want).abs() / want.abs().max(scale);
        worst_max = worst_max.max(rel(c.max, max));
        worst_min = worst_min.max(rel(c.min, min));
        nodes += 1;
    }
    (worst_max, worst_min, nodes)
}

/// A cylinder of radius 10 mm: `max` 1/R, `min` 0, at 24, 48 and 96 nodes round.
/// The error falls as the mesh refines, and is within 1 % at 48 round.
#[test]
fn a_tessellated_cylinder_has_its_radius() {
    let r = 10.0;
    let mut errors = Vec::new();
    for n in [24, 48, 96] {
        let surface =
            |u: f64, v: f64| DVec3::new(r * (TAU * u).cos(), r * (TAU * u).sin(), 40.0 * v);
        let outward = |u: f64, _: f64| DVec3::new((TAU * u).cos(), (TAU * u).sin(), 0.0);
        let (mesh, params) = grid_mesh(n, 8, (true, false), &surface, &outward);
        // Off the open ends, where a node's neighbours lie on one side only.
        let keep = |_: f64, v: f64| v > 0.01 && v < 0.99;
        let (max, min, nodes) =
            worst_errors(&mesh, &params, &keep, &|_, _| (1.0 / r, 0.0), 1.0 / r);
        eprintln!("cylinder R {r}, {n} round: {nodes} nodes, worst max {max:.2e}, worst min {min:.2e} (relative to 1/R)");
        errors.push(max.max(min));
    }
    assert!(errors[1] < 0.01, "{errors:?}");
    assert!(errors[2] < errors[0], "{errors:?}");
}

/// A sphere of radius 25 mm (a latitude-longitude grid): every curvature 1/R, at nodes
/// within 60 deg of the equator (the poles' fans are not a die face's mesh).
#[test]
fn a_tessellated_sphere_has_its_radius() {
    let r = 25.0;
    let mut errors = Vec::new();
    for n in [24, 48, 96] {
        let surface = |u: f64, v: f64| {
            let (lon, lat) = (TAU * u, PI * (v - 0.5));
            r * DVec3::new(lat.cos() * lon.cos(), lat.cos() * lon.sin(), lat.sin())
        };
        let outward = |u: f64, v: f64| surface(u, v) / r;
        let (mesh, params) = grid_mesh(n, n / 2, (true, false), &surface, &outward);
        let keep = |_: f64, v: f64| (PI * (v - 0.5)).abs() < PI / 3.0;
        let (max, min, nodes) =
            worst_errors(&mesh, &params, &keep, &|_, _| (1.0 / r, 1.0 / r), 1.0 / r);
        eprintln!(
            "sphere R {r}, {n} round: {nodes} nodes, worst max {max:.2e}, worst min {min:.2e}"
        );
        errors.push(max.max(min));
    }
    assert!(errors[1] < 0.02, "{errors:?}");
    assert!(errors[2] < errors[0], "{errors:?}");
}

/// A torus, 40 mm across its ring and a 6 mm tube: round the tube 1/r, along the ring
/// cos v / (R + r cos v), which changes sign from the outside (convex) to the inside
/// (a saddle). Errors are taken relative to 1/r.
#[test]
fn a_tessellated_torus_has_both_its_curvatures() {
    let (big, small) = (20.0, 6.0);
    let mut errors = Vec::new();
    for n in [32, 64, 128] {
        let point = |u: f64, v: f64| {
            let (a, b) = (TAU * u, TAU * v);
            DVec3::new(
                (big + small * b.cos()) * a.cos(),
                (big + small * b.cos()) * a.sin(),
                small * b.sin(),
            )
        };
        let outward = |u: f64, v: f64| {
            let (a, b) = (TAU * u, TAU * v);
            DVec3::new(b.cos() * a.cos(), b.cos() * a.sin(), b.sin())
        };
        let (mesh, params) = grid_mesh(n, n / 2, (true, true), &point, &outward);
        let exact = |_: f64, v: f64| {
            let ring = (TAU * v).cos() / (big + small * (TAU * v).cos());
            let tube = 1.0 / small;
            (tube.max(ring), tube.min(ring))
        };
        let (max, min, nodes) = worst_errors(&mesh, &params, &|_, _| true, &exact, 1.0 / small);
        eprintln!("torus R {big} r {small}, {n} x {}: {nodes} nodes, worst max {max:.2e}, worst min {min:.2e} (relative to 1/r)", n / 2);
        errors.push(max.max(min));
    }
    assert!(errors[1] < 0.03, "{errors:?}");
    assert!(errors[2] < errors[0], "{errors:?}");
}

/// A flat grid has no curvature, and a mesh scaled by 1000 has curvatures divided by
/// 1000 (the fit is scaled to each neighbourhood, so a 0.01 mm mesh fits as well as a
/// 10 m one).
#[test]
fn a_flat_has_none_and_scale_divides_curvature() {
    let plane = |u: f64, v: f64| DVec3::new(100.0 * u, 100.0 * v, 0.0);
    let (mesh, params) = grid_mesh(10, 10, (false, false), &plane, &|_, _| DVec3::Z);
    let found = node_curvatures(&mesh);
    for (k, c) in found.iter().enumerate() {
        let (u, v) = params[k];
        if u > 0.0 && u < 1.0 && v > 0.0 && v < 1.0 {
            let c = c.expect("a curvature");
            assert!(c.max.abs() < 1e-12 && c.min.abs() < 1e-12, "{c:?}");
        }
    }
    let r = 10.0;
    for factor in [1e-3, 1.0, 1e3] {
        let surface =
            |u: f64, v: f64| factor * r * DVec3::new((TAU * u).cos(), (TAU * u).sin(), 4.0 * v);
        let outward = |u: f64, _: f64| DVec3::new((TAU * u).cos(), (TAU * u).sin(), 0.0);
        let (mesh, _) = grid_mesh(48, 8, (true, false), &surface, &outward);
        let c = node_curvatures(&mesh)[48 * 4].expect("a curvature");
        assert!(((c.max * factor * r) - 1.0).abs() < 0.01, "{factor}: {c:?}");
        assert!((c.radius() / (factor * r) - 1.0).abs() < 0.01);
    }
}
