//! Tessellation honours its tolerance: dense interior sampling of every triangle (and of
//! every polyline segment) against the true surface (curve), for a set of test surfaces
//! at 0.1, 0.01 and 0.001 mm; plus watertightness, orientation, normals, near-optimal
//! counts and the handling of kinks, collapsed edges and invalid tolerances.

use std::collections::BTreeMap;
use std::f64::consts::{FRAC_1_SQRT_2, PI};

use dieface::geom::tessellate::{
    tessellate_curve, tessellate_surface, Polyline, SurfaceMesh, Tolerance,
};
use dieface::geom::{GeomError, NurbsCurve, NurbsSurface, Point};
use glam::{DVec2, DVec3};

const TOLERANCES: [f64; 3] = [0.1, 0.01, 0.001];

// ---------------------------------------------------------------- test surfaces

fn clamped(degree: usize, interior: &[f64]) -> Vec<f64> {
    let mut k = vec![0.0; degree + 1];
    k.extend_from_slice(interior);
    k.extend(std::iter::repeat_n(1.0, degree + 1));
    k
}

/// A flat bilinear rectangle, 100 x 80 mm.
fn plane() -> NurbsSurface {
    let net = vec![
        vec![DVec3::new(0.0, 0.0, 5.0), DVec3::new(0.0, 80.0, 5.0)],
        vec![DVec3::new(100.0, 0.0, 5.0), DVec3::new(100.0, 80.0, 5.0)],
    ];
    NurbsSurface::new(1, 1, clamped(1, &[]), clamped(1, &[]), net).unwrap()
}

const CYL_R: f64 = 50.0;
const CYL_H: f64 = 100.0;

/// The exact quarter cylinder of radius 50 mm and height 100 mm: a rational quadratic
/// quarter circle in u, a straight ruling in v.
fn quarter_cylinder() -> NurbsSurface {
    let r = CYL_R;
    let ring = [
        DVec3::new(r, 0.0, 0.0),
        DVec3::new(r, r, 0.0),
        DVec3::new(0.0, r, 0.0),
    ];
    let net = ring
        .iter()
        .map(|&p| vec![p, p + DVec3::Z * CYL_H])
        .collect();
    let w = [1.0, FRAC_1_SQRT_2, 1.0];
    let weights = w.iter().map(|&wi| vec![wi, wi]).collect();
    NurbsSurface::new_rational(2, 1, clamped(2, &[]), clamped(1, &[]), net, weights).unwrap()
}

/// A wavy bicubic, 100 x 80 mm, several knot spans and a C0 (triple) knot at u = 0.5.
fn wavy() -> NurbsSurface {
    let ku = clamped(3, &[0.3, 0.5, 0.5, 0.5, 0.8]); // 9 control points along u
    let kv = clamped(3, &[0.25, 0.5, 0.75]); // 7 along v
    let net = (0..9)
        .map(|i| {
            (0..7)
                .map(|j| {
                    let (x, y) = (100.0 * i as f64 / 8.0, 80.0 * j as f64 / 6.0);
                    DVec3::new(x, y, 6.0 * (1.3 * i as f64).sin() * (0.9 * j as f64).cos())
                })
                .collect()
        })
        .collect();
    NurbsSurface::new(3, 3, ku, kv, net).unwrap()
}

/// A degree-5 Bezier bump, 60 x 60 mm, 15 mm high control points in the middle.
fn bump() -> NurbsSurface {
    let net = (0..6)
        .map(|i| {
            (0..6)
                .map(|j| {
                    let z = if (2..=3).contains(&i) && (2..=3).contains(&j) {
                        15.0
                    } else {
                        0.0
                    };
                    DVec3::new(12.0 * i as f64, 12.0 * j as f64, z)
                })
                .collect()
        })
        .collect();
    NurbsSurface::new(5, 5, clamped(5, &[]), clamped(5, &[]), net).unwrap()
}

const SPHERE_R: f64 = 30.0;

/// An exact sphere octant of radius 30 mm, rational biquadratic: u runs around the z
/// axis, v from the equator to the pole, where the whole edge v = 1 collapses to a point
/// (a three-sided patch).
fn sphere_octant() -> NurbsSurface {
    let r = SPHERE_R;
    let meridian = [(r, 0.0, 1.0), (r, r, FRAC_1_SQRT_2), (0.0, r, 1.0)]; // (radius, z, weight)
    let around = [(1.0, 0.0, 1.0), (1.0, 1.0, FRAC_1_SQRT_2), (0.0, 1.0, 1.0)]; // (x, y, weight)
    let net = around
        .iter()
        .map(|&(x, y, _)| {
            meridian
                .iter()
                .map(|&(m, z, _)| DVec3::new(m * x, m * y, z))
                .collect()
        })
        .collect();
    let weights = around
        .iter()
        .map(|&(_, _, wu)| meridian.iter().map(|&(_, _, wv)| wu * wv).collect())
        .collect();
    NurbsSurface::new_rational(2, 2, clamped(2, &[]), clamped(2, &[]), net, weights).unwrap()
}

// ---------------------------------------------------------------- mesh checks

/// What the checks measured, for the report.
struct Report {
    triangles: usize,
    vertices: usize,
    max_deviation: f64,
}

/// Sides of the parameter domain a vertex lies on: 0 = u0, 1 = u1, 2 = v0, 3 = v1. A
/// vertex welded at a collapsed edge also lies on the sides of the domain corners it
/// coincides with.
fn sides(s: &NurbsSurface, uv: DVec2, p: DVec3) -> [bool; 4] {
    let ((u0, u1), (v0, v1)) = (s.domain_u(), s.domain_v());
    let mut out = [uv.x == u0, uv.x == u1, uv.y == v0, uv.y == v1];
    for (cu, cv, a, b) in [
        (u0, v0, 0, 2),
        (u1, v0, 1, 2),
        (u0, v1, 0, 3),
        (u1, v1, 1, 3),
    ] {
        if s.point_at(cu, cv).distance(p) < 1e-9 {
            out[a] = true;
            out[b] = true;
        }
    }
    out
}

/// Whether the iso-line through `uv` in u or in v collapses to a point (where the
/// surface normal is undefined and `NurbsSurface::normal` may return noise).
fn on_collapsed_edge(s: &NurbsSurface, uv: DVec2) -> bool {
    let ((u0, u1), (v0, v1)) = (s.domain_u(), s.domain_v());
    let p = s.point_at(uv.x, uv.y);
    let along_u = [u0, 0.5 * (u0 + u1), u1]
        .iter()
        .all(|&u| s.point_at(u, uv.y).distance(p) < 1e-9);
    let along_v = [v0, 0.5 * (v0 + v1), v1]
        .iter()
        .all(|&v| s.point_at(uv.x, v).distance(p) < 1e-9);
    along_u || along_v
}

/// Checks the mesh and returns the largest deviation found by dense sampling.
fn check_mesh(
    name: &str,
    s: &NurbsSurface,
    mesh: &SurfaceMesh,
    tol: f64,
    per_side: usize,
) -> Report {
    let n = mesh.positions.len();
    assert_eq!(mesh.uv.len(), n, "{name}: uv count");
    assert_eq!(mesh.normals.len(), n, "{name}: normal count");
    assert!(!mesh.triangles.is_empty(), "{name}: no triangles");

    // Vertices on the surface, unit normals agreeing with the surface normal.
    let mut degenerate = vec![false; n];
    for (i, flag) in degenerate.iter_mut().enumerate() {
        let uv = mesh.uv[i];
        let p = s.point_at(uv.x, uv.y);
        assert!(
            p.distance(mesh.positions[i]) < 1e-9,
            "{name}: vertex {i} off the surface"
        );
        assert!(
            (mesh.normals[i].length() - 1.0).abs() < 1e-9,
            "{name}: normal {i} not unit"
        );
        if on_collapsed_edge(s, uv) {
            *flag = true;
        } else {
            let sn = s.normal(uv.x, uv.y).unwrap();
            assert!(
                sn.dot(mesh.normals[i]) > 0.999,
                "{name}: normal {i} disagrees with the surface"
            );
        }
    }

    // Watertight: every edge used once (domain boundary) or twice (interior), never
    // twice in the same direction (consistent orientation).
    let mut edges: BTreeMap<(u32, u32), (usize, usize)> = BTreeMap::new();
    for t in &mesh.triangles {
        assert!(
            t.iter().all(|&i| (i as usize) < n),
            "{name}: index out of range"
        );
        assert!(
            t[0] != t[1] && t[1] != t[2] && t[2] != t[0],
            "{name}: degenerate triangle {t:?}"
        );
        for e in 0..3 {
            let (a, b) = (t[e], t[(e + 1) % 3]);
            let entry = edges.entry((a.min(b), a.max(b))).or_default();
            if a < b {
                entry.0 += 1;
            } else {
                entry.1 += 1;
            }
        }
    }
    for (&(a, b), &(fwd, back)) in &edges {
        assert!(
            fwd <= 1 && back <= 1,
            "{name}: edge {a}-{b} used {fwd}+{back} times"
        );
        if fwd + back == 1 {
            let (sa, sb) = (a as usize, b as usize);
            let side_a = sides(s, mesh.uv[sa], mesh.positions[sa]);
            let side_b = sides(s, mesh.uv[sb], mesh.positions[sb]);
            assert!(
                (0..4).any(|k| side_a[k] && side_b[k]),
                "{name}: free edge {a}-{b} inside the domain ({} {})",
                mesh.uv[sa],
                mesh.uv[sb]
            );
        }
    }

    // Orientation and dense interior sampling.
    let mut worst: f64 = 0.0;
    for t in &mesh.triangles {
        let [a, b, c] = t.map(|i| i as usize);
        let p = [mesh.positions[a], mesh.positions[b], mesh.positions[c]];
        // Parameter candidates per corner: its own uv, and at a collapsed edge the uv the
        // neighbouring corners suggest (any surface point bounds the distance from above).
        let corners = [a, b, c];
        let cands: Vec<Vec<DVec2>> = (0..3)
            .map(|m| {
                let own = mesh.uv[corners[m]];
                let mut list = vec![own];
                if degenerate[corners[m]] {
                    for o in (0..3).filter(|&o| o != m) {
                        let other = mesh.uv[corners[o]];
                        for cand in [DVec2::new(other.x, own.y), DVec2::new(own.x, other.y)] {
                            if s.point_at(cand.x, cand.y).distance(p[m]) < 1e-9 {
                                list.push(cand);
                            }
                        }
                    }
                }
                list
            })
            .collect();
        let centroid_uv = (cands[0][0] + cands[1][0] + cands[2][0]) / 3.0;
        let face = (p[1] - p[0]).cross(p[2] - p[0]);
        if let Ok(sn) = s.normal(centroid_uv.x, centroid_uv.y) {
            assert!(
                face.dot(sn) > 0.0,
                "{name}: triangle {t:?} wound against S_u x S_v"
            );
        }
        for i in 0..=per_side {
            for j in 0..=per_side - i {
                let b = DVec3::new(i as f64, j as f64, (per_side - i - j) as f64) / per_side as f64;
                let q = p[0] * b.x + p[1] * b.y + p[2] * b.z;
                let mut best = f64::INFINITY;
                for &ua in &cands[0] {
                    for &ub in &cands[1] {
                        for &uc in &cands[2] {
                            let uv = ua * b.x + ub * b.y + uc * b.z;
                            best = best.min(s.point_at(uv.x, uv.y).distance(q));
                        }
                    }
                }
                worst = worst.max(best);
            }
        }
    }
    assert!(
        worst <= tol,
        "{name}: deviation {worst} exceeds the tolerance {tol}"
    );
    Report {
        triangles: mesh.triangles.len(),
        vertices: n,
        max_deviation: worst,
    }
}

/// Tessellates at the three tolerances, checks everything, prints a summary line each.
fn check_surface(name: &str, s: &NurbsSurface) -> Vec<Report> {
    TOLERANCES
        .iter()
        .map(|&tol| {
            let start = std::time::Instant::now();
            let mesh = tessellate_surface(s, &Tolerance::new(tol).unwrap()).unwrap();
            let took = start.elapsed();
            let per_side = if mesh.triangles.len() > 60_000 { 4 } else { 10 };
            let r = check_mesh(name, s, &mesh, tol, per_side);
            println!(
                "{name:>10} tol {tol:<6} {:>7} triangles {:>7} vertices  max deviation {:.4e} ({:.1} %)  {:.1} ms",
                r.triangles,
                r.vertices,
                r.max_deviation,
                100.0 * r.max_deviation / tol,
                took.as_secs_f64() * 1e3
            );
            r
        })
        .collect()
}

// ---------------------------------------------------------------- surface tests

#[test]
fn plane_needs_two_triangles() {
    for r in check_surface("plane", &plane()) {
        assert_eq!(r.triangles, 2);
        assert_eq!(r.vertices, 4);
    }
}

#[test]
fn quarter_cylinder_within_tolerance_and_near_optimal() {
    let reports = check_surface("cylinder", &quarter_cylinder());
    for (r, tol) in reports.iter().zip(TOLERANCES) {
        // The step rule: chords of angle 2 acos(1 - tol / R) around the axis, one row of
        // quads along the straight rulings.
        let chords = ((PI / 2.0) / (2.0 * (1.0 - tol / CYL_R).acos())).ceil() as usize;
        let optimal = 2 * chords;
        assert!(
            r.triangles >= optimal,
            "tol {tol}: {} triangles, fewer than possible ({optimal})",
            r.triangles
        );
        assert!(
            r.triangles <= 2 * optimal,
            "tol {tol}: {} triangles, over twice the need {optimal}",
            r.triangles
        );
    }
}

#[test]
fn wavy_bicubic_with_c0_knot_within_tolerance() {
    let s = wavy();
    let reports = check_surface("wavy", &s);
    // The C0 knot line u = 0.5 must be a grid line (the crease is kept exactly).
    let mesh = tessellate_surface(&s, &Tolerance::new(0.1).unwrap()).unwrap();
    assert!(
        mesh.uv.iter().any(|uv| uv.x == 0.5),
        "the C0 knot is not a vertex line"
    );
    assert!(reports.windows(2).all(|w| w[1].triangles > w[0].triangles));
}

#[test]
fn degree_five_bump_within_tolerance() {
    check_surface("bump", &bump());
}

#[test]
fn sphere_octant_with_collapsed_edge() {
    let s = sphere_octant();
    for (r, tol) in check_surface("sphere", &s).iter().zip(TOLERANCES) {
        assert!(r.max_deviation <= tol);
    }
    // Exactly one vertex at the pole, and its normal points up.
    let mesh = tessellate_surface(&s, &Tolerance::new(0.01).unwrap()).unwrap();
    let pole = DVec3::new(0.0, 0.0, SPHERE_R);
    let at_pole: Vec<usize> = (0..mesh.positions.len())
        .filter(|&i| mesh.positions[i].distance(pole) < 1e-9)
        .collect();
    assert_eq!(at_pole.len(), 1, "pole vertices: {at_pole:?}");
    assert!(mesh.normals[at_pole[0]].dot(DVec3::Z) > 0.999);
    // On the sphere the distance to the surface is exact: | |x| - R |.
    for t in &mesh.triangles {
        let p = t.map(|i| mesh.positions[i as usize]);
        for k in 0..=10 {
            for l in 0..=10 - k {
                let q = (p[0] * k as f64 + p[1] * l as f64 + p[2] * (10 - k - l) as f64) / 10.0;
                assert!((q.length() - SPHERE_R).abs() <= 0.01);
            }
        }
    }
}

#[test]
fn surface_angle_and_edge_limits() {
    // The plane gets subdivided by the edge limit only.
    let tol = Tolerance::new(0.1).unwrap().with_max_edge(10.0).unwrap();
    let mesh = tessellate_surface(&plane(), &tol).unwrap();
    for t in &mesh.triangles {
        for e in 0..3 {
            let len =
                mesh.positions[t[e] as usize].distance(mesh.positions[t[(e + 1) % 3] as usize]);
            assert!(len <= 10.0 + 1e-9, "edge {len}");
        }
    }
    check_mesh("plane/edge", &plane(), &mesh, 0.1, 4);
    // A coarse chordal tolerance leaves the angle limit in charge on the cylinder.
    let angle = 5f64.to_radians();
    let tol = Tolerance::new(5.0).unwrap().with_angle(angle).unwrap();
    let mesh = tessellate_surface(&quarter_cylinder(), &tol).unwrap();
    let mut max_turn: f64 = 0.0;
    for t in &mesh.triangles {
        for e in 0..3 {
            let (a, b) = (
                mesh.normals[t[e] as usize],
                mesh.normals[t[(e + 1) % 3] as usize],
            );
            max_turn = max_turn.max(a.angle_between(b));
        }
    }
    assert!(max_turn <= angle * 1.0001, "normal turn {max_turn}");
    assert!(mesh.triangles.len() <= 2 * 2 * (90.0f64 / 5.0).ceil() as usize);
}

/// The tessellation converts to a kernel mesh whose half-edge topology sees one disc:
/// one boundary loop along the domain's edges, consistent orientation, no free edge
/// inside (the sphere octant's collapsed edge is welded, so it is a disc too).
#[test]
fn tessellation_is_a_manifold_disc_mesh() {
    for s in [wavy(), sphere_octant(), quarter_cylinder()] {
        let tess = tessellate_surface(&s, &Tolerance::new(0.05).unwrap()).unwrap();
        let mesh = tess.to_mesh().unwrap();
        let topo = mesh.topology();
        assert!(topo.is_consistently_oriented());
        assert!(topo.non_manifold_edges().is_empty());
        assert_eq!(topo.euler_characteristic(), 1, "a disc");
        let loops = topo.boundary_loops();
        assert_eq!(loops.loops.len(), 1);
        assert!(loops.open_chains.is_empty());
        assert_eq!(
            mesh.normals().map(<[DVec3]>::len),
            Some(tess.positions.len())
        );
    }
}

#[test]
fn surface_tessellation_is_deterministic() {
    let tol = Tolerance::new(0.01).unwrap();
    for s in [wavy(), sphere_octant()] {
        assert_eq!(
            tessellate_surface(&s, &tol).unwrap(),
            tessellate_surface(&s, &tol).unwrap()
        );
    }
}

#[test]
fn runaway_refinement_is_an_error() {
    // A 10 km sphere octant at a micrometre tolerance needs billions of triangles.
    let big = sphere_octant().map_points(|p| p * 3.0e5);
    let err = tessellate_surface(&big, &Tolerance::new(1e-3).unwrap()).unwrap_err();
    assert!(matches!(err, GeomError::NoConvergence { .. }), "{err:?}");
}

#[test]
fn degenerate_surface_does_not_panic() {
    let p = DVec3::new(1.0, 2.0, 3.0);
    let s = NurbsSurface::new(
        1,
        1,
        clamped(1, &[]),
        clamped(1, &[]),
        vec![vec![p, p], vec![p, p]],
    )
    .unwrap();
    let mesh = tessellate_surface(&s, &Tolerance::new(0.1).unwrap()).unwrap();
    assert!(mesh.triangles.is_empty());
    assert!(mesh
        .normals
        .iter()
        .all(|n| (n.length() - 1.0).abs() < 1e-12));
}

// ---------------------------------------------------------------- tolerances

#[test]
fn tolerance_validation() {
    assert!(matches!(
        Tolerance::new(0.0),
        Err(GeomError::NotPositive { .. })
    ));
    assert!(matches!(
        Tolerance::new(-1.0),
        Err(GeomError::NotPositive { .. })
    ));
    assert!(matches!(
        Tolerance::new(f64::NAN),
        Err(GeomError::NotFinite { .. })
    ));
    assert!(matches!(
        Tolerance::new(f64::INFINITY),
        Err(GeomError::NotFinite { .. })
    ));
    let ok = Tolerance::new(0.01).unwrap();
    assert!((ok.angle - 15f64.to_radians()).abs() < 1e-12);
    assert!(ok.with_angle(0.0).is_err());
    assert!(ok.with_max_edge(-2.0).is_err());
    // Public fields are validated on entry too.
    let bad = Tolerance {
        chordal: -0.1,
        ..ok
    };
    assert!(tessellate_surface(&plane(), &bad).is_err());
    assert!(tessellate_curve(&NurbsCurve::line(DVec3::ZERO, DVec3::X).unwrap(), &bad).is_err());
}

// ---------------------------------------------------------------- curves

/// Largest distance from densely sampled curve points of each segment's interval to
/// that segment.
fn polyline_deviation<P: Point>(c: &NurbsCurve<P>, line: &Polyline<P>, samples: usize) -> f64 {
    let mut worst: f64 = 0.0;
    assert_eq!(line.params.len(), line.points.len());
    for w in 0..line.params.len() - 1 {
        let (t0, t1) = (line.params[w], line.params[w + 1]);
        assert!(t1 > t0, "parameters not increasing");
        let (a, b) = (line.points[w], line.points[w + 1]);
        assert!(a.distance(c.point_at(t0)) < 1e-12);
        let ab = b - a;
        for k in 1..samples {
            let q = c.point_at(t0 + (t1 - t0) * k as f64 / samples as f64);
            let s = ((q - a).dot(ab) / ab.dot(ab).max(1e-300)).clamp(0.0, 1.0);
            worst = worst.max((q - a - ab * s).length());
        }
    }
    worst
}

fn circle(r: f64) -> NurbsCurve<DVec2> {
    let h = FRAC_1_SQRT_2;
    let pts = [
        (1., 0.),
        (1., 1.),
        (0., 1.),
        (-1., 1.),
        (-1., 0.),
        (-1., -1.),
        (0., -1.),
        (1., -1.),
        (1., 0.),
    ];
    let w = vec![1.0, h, 1.0, h, 1.0, h, 1.0, h, 1.0];
    let knots = vec![0., 0., 0., 0.25, 0.25, 0.5, 0.5, 0.75, 0.75, 1., 1., 1.];
    NurbsCurve::new_rational(
        2,
        knots,
        pts.iter().map(|&(x, y)| DVec2::new(x, y) * r).collect(),
        w,
    )
    .unwrap()
}

#[test]
fn circle_within_tolerance_and_near_optimal() {
    let r = 50.0;
    let c = circle(r);
    for tol in TOLERANCES {
        let line = tessellate_curve(&c, &Tolerance::new(tol).unwrap()).unwrap();
        let dev = polyline_deviation(&c, &line, 200);
        let segments = line.segment_count();
        let analytic = 2.0 * PI / (2.0 * (1.0 - tol / r).acos());
        println!("circle R {r} tol {tol}: {segments} segments (analytic {analytic:.1}), max deviation {dev:.4e}");
        assert!(dev <= tol, "tol {tol}: deviation {dev}");
        assert!(
            segments as f64 >= analytic.floor(),
            "fewer segments than possible"
        );
        assert!(
            (segments as f64) <= 1.06 * analytic + 4.0,
            "{segments} segments, analytic {analytic}"
        );
        // The quarter points (double knots of a quadratic: C0 in the knot sense) are kept.
        for q in [0.25, 0.5, 0.75] {
            assert!(line.params.contains(&q));
        }
        assert_eq!(line.params.first(), Some(&0.0));
        assert_eq!(line.params.last(), Some(&1.0));
    }
}

#[test]
fn straight_line_is_one_segment_or_edge_limited() {
    let c = NurbsCurve::line(DVec3::ZERO, DVec3::new(95.0, 0.0, 0.0)).unwrap();
    let line = tessellate_curve(&c, &Tolerance::new(0.001).unwrap()).unwrap();
    assert_eq!(line.segment_count(), 1);
    // A straight cubic (collinear control points): still one segment.
    let pts: Vec<DVec3> = [0.0, 10.0, 60.0, 95.0]
        .iter()
        .map(|&x| DVec3::new(x, x, 0.0))
        .collect();
    let cubic = NurbsCurve::bezier(pts).unwrap();
    let line = tessellate_curve(&cubic, &Tolerance::new(0.001).unwrap()).unwrap();
    assert_eq!(line.segment_count(), 1);
    // L_max = 10 mm: ten segments of at most 10 mm over 95 mm.
    let tol = Tolerance::new(0.01).unwrap().with_max_edge(10.0).unwrap();
    let line = tessellate_curve(&c, &tol).unwrap();
    assert!(line
        .points
        .windows(2)
        .all(|w| w[0].distance(w[1]) <= 10.0 + 1e-9));
    assert_eq!(line.segment_count(), 10);
}

#[test]
fn kink_is_kept_as_a_vertex() {
    // Quadratic with a double knot at 0.4: the curve passes through (10, 10) with a
    // corner there.
    let pts = vec![
        DVec3::new(0.0, 0.0, 0.0),
        DVec3::new(5.0, 8.0, 0.0),
        DVec3::new(10.0, 10.0, 0.0),
        DVec3::new(16.0, 6.0, 0.0),
        DVec3::new(20.0, 0.0, 0.0),
    ];
    let c = NurbsCurve::new(2, vec![0., 0., 0., 0.4, 0.4, 1., 1., 1.], pts).unwrap();
    for tol in TOLERANCES {
        let line = tessellate_curve(&c, &Tolerance::new(tol).unwrap()).unwrap();
        let k = line
            .params
            .iter()
            .position(|&t| t == 0.4)
            .expect("the kink is not a vertex");
        assert!(line.points[k].distance(DVec3::new(10.0, 10.0, 0.0)) < 1e-12);
        assert!(polyline_deviation(&c, &line, 100) <= tol);
    }
}

#[test]
fn varying_curvature_cubic_within_tolerance() {
    // A cubic with tight and loose turns and several spans; the step rule alone (taken
    // from the curvature at the chord's start) would overshoot where curvature grows.
    let pts: Vec<DVec3> = [
        (0., 0., 0.),
        (30., 0., 5.),
        (32., 20., 0.),
        (10., 25., -5.),
        (12., 4., 0.),
        (60., 2., 10.),
        (80., 40., 0.),
    ]
    .iter()
    .map(|&(x, y, z)| DVec3::new(x, y, z))
    .collect();
    let c = NurbsCurve::new(3, vec![0., 0., 0., 0., 0.2, 0.45, 0.7, 1., 1., 1., 1.], pts).unwrap();
    let mut last = 0;
    for tol in TOLERANCES {
        let line = tessellate_curve(&c, &Tolerance::new(tol).unwrap()).unwrap();
        let dev = polyline_deviation(&c, &line, 200);
        println!(
            "cubic tol {tol}: {} segments, max deviation {dev:.4e}",
            line.segment_count()
        );
        assert!(dev <= tol, "tol {tol}: {dev}");
        assert!(line.segment_count() > last);
        last = line.segment_count();
        // Neighbouring tangents turn at most the default 15 degrees.
        for w in line.params.windows(2) {
            let (a, b) = (c.derivative_at(w[0]), c.derivative_at(w[1]));
            assert!(a.angle_between(b) <= 15f64.to_radians() + 1e-9);
        }
    }
    assert_eq!(
        tessellate_curve(&c, &Tolerance::new(0.01).unwrap()).unwrap(),
        tessellate_curve(&c, &Tolerance::new(0.01).unwrap()).unwrap()
    );
}
