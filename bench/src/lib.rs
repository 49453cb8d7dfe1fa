//! Shared fixtures and benchmark rows for comparing the dieface NURBS kernel with the
//! `curvo` crate.
//!
//! Every fixture is built once from plain data (degree, knots, Euclidean control points,
//! weights) and handed to both libraries: dieface stores Euclidean points and separate
//! weights, curvo stores homogeneous points `(w x, w y, w z, w)`. [`Fixtures::new`]
//! checks on every sample parameter that both libraries evaluate the same points and
//! derivatives (to 1e-9 mm, relative for derivatives), so every row provably times the
//! same geometry.
//!
//! The rows themselves ([`eval_rows`], [`tessellation_rows`]) are shared by the criterion
//! benchmark (`benches/kernel.rs`) and by the table printer (`src/bin/table.rs`).

use std::hint::black_box;
use std::time::{Duration, Instant};

use curvo::prelude::{AdaptiveTessellationOptions, NurbsCurve3D, NurbsSurface3D, Tessellation};
use dieface::geom::tessellate::{tessellate_surface, SurfaceMesh, Tolerance};
use dieface::geom::{Curve3, NurbsSurface};
use glam::{DVec2, DVec3};
use nalgebra::Point4;

/// Chordal tolerance of the tessellation rows, in millimetres.
pub const CHORDAL: f64 = 0.01;

/// Number of parameter samples per curve and per surface.
pub const SAMPLES: usize = 400;

/// Absolute tolerance on points (mm) when checking that both libraries agree.
pub const AGREE: f64 = 1e-9;

/// Small deterministic generator (no dependency on `rand`): splitmix64.
pub struct Rng(u64);

impl Rng {
    pub fn new(seed: u64) -> Self {
        Self(seed)
    }
    /// Uniform in [0, 1).
    pub fn next_f64(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^= z >> 31;
        (z >> 11) as f64 / (1u64 << 53) as f64
    }
    /// Uniform in [a, b).
    pub fn range(&mut self, a: f64, b: f64) -> f64 {
        a + (b - a) * self.next_f64()
    }
}

/// One curve given to both libraries, with its sample parameters.
pub struct CurvePair {
    pub name: &'static str,
    pub ours: Curve3,
    pub theirs: NurbsCurve3D<f64>,
    pub params: Vec<f64>,
}

/// One surface given to both libraries, with its sample parameters.
pub struct SurfacePair {
    pub name: &'static str,
    pub ours: NurbsSurface,
    pub theirs: NurbsSurface3D<f64>,
    pub params: Vec<(f64, f64)>,
}

/// Builds both curves from the same plain data.
pub fn curve_pair(
    name: &'static str,
    degree: usize,
    knots: Vec<f64>,
    points: Vec<DVec3>,
    weights: Option<Vec<f64>>,
    params: Vec<f64>,
) -> CurvePair {
    let w = weights.clone().unwrap_or_else(|| vec![1.0; points.len()]);
    let homogeneous: Vec<Point4<f64>> = points
        .iter()
        .zip(&w)
        .map(|(p, &w)| Point4::new(p.x * w, p.y * w, p.z * w, w))
        .collect();
    let theirs =
        NurbsCurve3D::<f64>::try_new(degree, homogeneous, knots.clone()).expect("curvo curve");
    let ours = match weights {
        Some(w) => Curve3::new_rational(degree, knots, points, w),
        None => Curve3::new(degree, knots, points),
    }
    .expect("dieface curve");
    CurvePair {
        name,
        ours,
        theirs,
        params,
    }
}

/// Builds both surfaces from the same plain data (`net[i][j]`, `i` along u, in both).
pub fn surface_pair(
    name: &'static str,
    degrees: (usize, usize),
    knots: (Vec<f64>, Vec<f64>),
    net: Vec<Vec<DVec3>>,
    weights: Option<Vec<Vec<f64>>>,
    params: Vec<(f64, f64)>,
) -> SurfacePair {
    let w = weights
        .clone()
        .unwrap_or_else(|| net.iter().map(|row| vec![1.0; row.len()]).collect());
    let homogeneous: Vec<Vec<Point4<f64>>> = net
        .iter()
        .zip(&w)
        .map(|(row, wr)| {
            row.iter()
                .zip(wr)
                .map(|(p, &w)| Point4::new(p.x * w, p.y * w, p.z * w, w))
                .collect()
        })
        .collect();
    let theirs = NurbsSurface3D::<f64>::new(
        degrees.0,
        degrees.1,
        knots.0.clone(),
        knots.1.clone(),
        homogeneous,
    );
    let ours = match weights {
        Some(w) => NurbsSurface::new_rational(degrees.0, degrees.1, knots.0, knots.1, net, w),
        None => NurbsSurface::new(degrees.0, degrees.1, knots.0, knots.1, net),
    }
    .expect("dieface surface");
    SurfacePair {
        name,
        ours,
        theirs,
        params,
    }
}

/// A clamped knot vector on [0, 1] with the given interior knots.
fn clamped(degree: usize, interior: &[f64]) -> Vec<f64> {
    let mut k = vec![0.0; degree + 1];
    k.extend_from_slice(interior);
    k.extend(std::iter::repeat_n(1.0, degree + 1));
    k
}

/// Sample parameters strictly inside (0, 1), away from knots by construction of the
/// generator (a knot hit has probability zero; at a knot the two libraries may pick
/// different spans for derivatives, which only matters for C1/C2 breaks).
fn curve_params(seed: u64) -> Vec<f64> {
    let mut rng = Rng::new(seed);
    (0..SAMPLES).map(|_| rng.range(1e-6, 1.0 - 1e-6)).collect()
}

fn surface_params(seed: u64) -> Vec<(f64, f64)> {
    let mut rng = Rng::new(seed);
    (0..SAMPLES)
        .map(|_| (rng.range(1e-6, 1.0 - 1e-6), rng.range(1e-6, 1.0 - 1e-6)))
        .collect()
}

/// A rational cubic space curve, 12 control points, non-uniform knots: a draw-bead or
/// trim line about 1.1 m long.
pub fn cubic_curve() -> CurvePair {
    let points: Vec<DVec3> = (0..12)
        .map(|i| {
            let s = i as f64 / 11.0;
            DVec3::new(
                -550.0 + 1100.0 * s + 25.0 * (7.0 * s).sin(),
                180.0 * (2.2 * s).sin() - 60.0 * s * s,
                40.0 + 65.0 * (3.1 * s + 0.4).cos() + 12.0 * (9.0 * s).sin(),
            )
        })
        .collect();
    let weights = vec![1.0, 0.8, 1.3, 0.6, 1.7, 1.0, 0.9, 1.5, 0.7, 1.2, 1.1, 1.0];
    let knots = clamped(3, &[0.07, 0.18, 0.26, 0.41, 0.5, 0.63, 0.81, 0.9]);
    curve_pair(
        "rational cubic, 12 pts",
        3,
        knots,
        points,
        Some(weights),
        curve_params(1),
    )
}

/// A polynomial degree-5 space curve, 14 control points, non-uniform knots.
pub fn quintic_curve() -> CurvePair {
    let points: Vec<DVec3> = (0..14)
        .map(|i| {
            let s = i as f64 / 13.0;
            DVec3::new(
                -400.0 + 800.0 * s,
                250.0 * (1.7 * s + 0.3).sin() + 30.0 * (11.0 * s).cos(),
                -20.0 + 90.0 * s * (1.0 - s) + 15.0 * (6.0 * s).sin(),
            )
        })
        .collect();
    let knots = clamped(5, &[0.1, 0.22, 0.3, 0.47, 0.55, 0.7, 0.76, 0.88]);
    curve_pair("degree-5, 14 pts", 5, knots, points, None, curve_params(2))
}

/// A bicubic 8 x 8 polynomial surface: a 1200 x 800 mm crowned panel with a feature.
pub fn bicubic_surface() -> SurfacePair {
    let xs: [f64; 8] = [-600.0, -470.0, -300.0, -110.0, 80.0, 260.0, 450.0, 600.0];
    let ys: [f64; 8] = [-400.0, -300.0, -170.0, -50.0, 60.0, 180.0, 310.0, 400.0];
    let net = (0..8)
        .map(|i| {
            (0..8)
                .map(|j| {
                    let (x, y) = (xs[i], ys[j]);
                    let crown =
                        140.0 * (1.0 - (x / 650.0).powi(2)) * (1.0 - 0.6 * (y / 450.0).powi(2));
                    let feature =
                        45.0 * (-((x - 120.0).powi(2) + (y + 60.0).powi(2)) / 40_000.0).exp();
                    DVec3::new(
                        x + 8.0 * (y / 200.0).sin(),
                        y + 6.0 * (x / 300.0).cos(),
                        crown + feature,
                    )
                })
                .collect()
        })
        .collect();
    let ku = clamped(3, &[0.12, 0.3, 0.55, 0.8]);
    let kv = clamped(3, &[0.2, 0.35, 0.6, 0.74]);
    surface_pair(
        "bicubic 8x8",
        (3, 3),
        (ku, kv),
        net,
        None,
        surface_params(3),
    )
}

/// A rational biquadratic 6 x 6 surface, weights 0.5 .. 2: a 900 x 700 mm flange-like
/// patch.
pub fn rational_surface() -> SurfacePair {
    let mut rng = Rng::new(4);
    let xs: [f64; 6] = [-450.0, -280.0, -90.0, 120.0, 300.0, 450.0];
    let ys: [f64; 6] = [-350.0, -190.0, -40.0, 110.0, 240.0, 350.0];
    let net = (0..6)
        .map(|i| {
            (0..6)
                .map(|j| {
                    let (x, y) = (xs[i], ys[j]);
                    let z = 90.0 * (x / 500.0).cos() * (y / 420.0).cos() + 0.08 * x - 0.05 * y;
                    DVec3::new(x, y, z)
                })
                .collect()
        })
        .collect();
    let weights = (0..6)
        .map(|_| (0..6).map(|_| rng.range(0.5, 2.0)).collect())
        .collect();
    let ku = clamped(2, &[0.2, 0.45, 0.7]);
    let kv = clamped(2, &[0.3, 0.5, 0.8]);
    surface_pair(
        "rational biquadratic 6x6",
        (2, 2),
        (ku, kv),
        net,
        Some(weights),
        surface_params(5),
    )
}

/// All fixtures, checked for agreement between the libraries.
pub struct Fixtures {
    pub cubic: CurvePair,
    pub quintic: CurvePair,
    pub bicubic: SurfacePair,
    pub rational: SurfacePair,
}

impl Fixtures {
    /// Builds every fixture and panics unless both libraries agree on all samples.
    pub fn new() -> Self {
        let f = Self {
            cubic: cubic_curve(),
            quintic: quintic_curve(),
            bicubic: bicubic_surface(),
            rational: rational_surface(),
        };
        for c in [&f.cubic, &f.quintic] {
            check_curve(c);
        }
        for s in [&f.bicubic, &f.rational] {
            check_surface(s);
        }
        f
    }
}

impl Default for Fixtures {
    fn default() -> Self {
        Self::new()
    }
}

fn dv(v: &nalgebra::Vector3<f64>) -> DVec3 {
    DVec3::new(v.x, v.y, v.z)
}

fn dp(p: &nalgebra::Point3<f64>) -> DVec3 {
    DVec3::new(p.x, p.y, p.z)
}

/// `|a - b| <= AGREE * max(1, |a|)`: absolute 1e-9 mm on points (|a| < 1e3 gives at most
/// a relative 1e-12 on coordinates), relative 1e-9 on derivatives, whose magnitudes grow
/// with the inverse powers of the parameter range.
fn agree(a: DVec3, b: DVec3, scale: f64) -> bool {
    (a - b).length() <= AGREE * scale.max(1.0)
}

/// Panics unless both curves agree in point, first and second derivative on all samples.
pub fn check_curve(c: &CurvePair) {
    for &t in &c.params {
        let p = c.ours.point_at(t);
        let q = dp(&c.theirs.point_at(t));
        assert!(
            (p - q).length() < AGREE,
            "{}: point at t={t}: dieface {p} vs curvo {q}",
            c.name
        );
        let d = c.ours.derivatives::<3>(t);
        let e = c.theirs.rational_derivatives(t, 2);
        for k in 0..3 {
            assert!(
                agree(d[k], dv(&e[k]), d[k].length()),
                "{}: derivative {k} at t={t}: dieface {} vs curvo {}",
                c.name,
                d[k],
                dv(&e[k])
            );
        }
    }
}

/// Panics unless both surfaces agree in point and all derivatives up to order 2.
pub fn check_surface(s: &SurfacePair) {
    for &(u, v) in &s.params {
        let p = s.ours.point_at(u, v);
        let q = dp(&s.theirs.point_at(u, v));
        assert!(
            (p - q).length() < AGREE,
            "{}: point at ({u}, {v}): dieface {p} vs curvo {q}",
            s.name
        );
        let d = s.ours.derivatives::<3>(u, v);
        let e = s.theirs.rational_derivatives(u, v, 2);
        for k in 0..=2 {
            for l in 0..=(2 - k) {
                assert!(
                    agree(d[k][l], dv(&e[k][l]), d[k][l].length()),
                    "{}: derivative ({k}, {l}) at ({u}, {v}): dieface {} vs curvo {}",
                    s.name,
                    d[k][l],
                    dv(&e[k][l])
                );
            }
        }
    }
}

/// A timed operation: one call runs `ops` evaluations (or one tessellation).
pub type Op<'a> = Box<dyn Fn() + 'a>;

/// One row of the comparison: the same work done by both libraries.
pub struct Row<'a> {
    /// Short identifier (criterion group name).
    pub id: String,
    /// Human-readable description for the table.
    pub label: String,
    /// Operations per call (to report time per evaluation).
    pub ops: usize,
    pub ours: Op<'a>,
    pub theirs: Op<'a>,
    /// Extra columns for tessellation rows.
    pub mesh: Option<MeshInfo>,
}

/// Triangle counts and measured deviations of both tessellations, plus curvo's settings.
#[derive(Debug, Clone)]
pub struct MeshInfo {
    pub ours_triangles: usize,
    pub ours_deviation: f64,
    pub theirs_triangles: usize,
    pub theirs_deviation: f64,
    pub theirs_settings: String,
}

/// Evaluation rows: every sample parameter evaluated once per call, by both libraries,
/// through their plain (stateless) evaluation methods.
pub fn eval_rows(f: &Fixtures) -> Vec<Row<'_>> {
    let mut rows = Vec::new();
    for c in [&f.cubic, &f.quintic] {
        let slug = if c.ours.degree() == 3 {
            "cubic"
        } else {
            "quintic"
        };
        rows.push(Row {
            id: format!("curve_point/{slug}"),
            label: format!("curve point, {}", c.name),
            ops: c.params.len(),
            ours: Box::new(move || {
                for &t in &c.params {
                    black_box(c.ours.point_at(black_box(t)));
                }
            }),
            theirs: Box::new(move || {
                for &t in &c.params {
                    black_box(c.theirs.point_at(black_box(t)));
                }
            }),
            mesh: None,
        });
    }
    for c in [&f.cubic, &f.quintic] {
        let slug = if c.ours.degree() == 3 {
            "cubic"
        } else {
            "quintic"
        };
        rows.push(Row {
            id: format!("curve_d2/{slug}"),
            label: format!("curve point + 2 derivatives, {}", c.name),
            ops: c.params.len(),
            ours: Box::new(move || {
                for &t in &c.params {
                    black_box(c.ours.derivatives::<3>(black_box(t)));
                }
            }),
            theirs: Box::new(move || {
                for &t in &c.params {
                    black_box(c.theirs.rational_derivatives(black_box(t), 2));
                }
            }),
            mesh: None,
        });
    }
    for (what, n, ours_n) in [
        ("surface point", 0usize, 0usize),
        ("surface point + 1st derivatives", 1, 2),
        ("surface point + 2nd derivatives", 2, 3),
    ] {
        for s in [&f.bicubic, &f.rational] {
            let slug = if s.ours.is_rational() {
                "rational"
            } else {
                "bicubic"
            };
            let id = match n {
                0 => format!("surface_point/{slug}"),
                1 => format!("surface_d1/{slug}"),
                _ => format!("surface_d2/{slug}"),
            };
            let ours: Op<'_> = match ours_n {
                0 => Box::new(move || {
                    for &(u, v) in &s.params {
                        black_box(s.ours.point_at(black_box(u), black_box(v)));
                    }
                }),
                2 => Box::new(move || {
                    for &(u, v) in &s.params {
                        black_box(s.ours.derivatives::<2>(black_box(u), black_box(v)));
                    }
                }),
                _ => Box::new(move || {
                    for &(u, v) in &s.params {
                        black_box(s.ours.derivatives::<3>(black_box(u), black_box(v)));
                    }
                }),
            };
            let theirs: Op<'_> = if n == 0 {
                Box::new(move || {
                    for &(u, v) in &s.params {
                        black_box(s.theirs.point_at(black_box(u), black_box(v)));
                    }
                })
            } else {
                Box::new(move || {
                    for &(u, v) in &s.params {
                        black_box(s.theirs.rational_derivatives(black_box(u), black_box(v), n));
                    }
                })
            };
            rows.push(Row {
                id,
                label: format!("{what}, {}", s.name),
                ops: s.params.len(),
                ours,
                theirs,
                mesh: None,
            });
        }
    }
    for s in [&f.bicubic, &f.rational] {
        let slug = if s.ours.is_rational() {
            "rational"
        } else {
            "bicubic"
        };
        // A regular grid over the domain, as curvo's `regular_sample_points` spaces it.
        let spaced = |(a, b): (f64, f64)| -> Vec<f64> {
            (0..=GRID_DIVS)
                .map(|i| a + (b - a) * i as f64 / GRID_DIVS as f64)
                .collect()
        };
        let (us, vs) = (spaced(s.ours.domain_u()), spaced(s.ours.domain_v()));
        rows.push(Row {
            id: format!("surface_grid/{slug}"),
            label: format!(
                "surface grid points ({} x {}), {}",
                GRID_DIVS + 1,
                GRID_DIVS + 1,
                s.name
            ),
            ops: (GRID_DIVS + 1) * (GRID_DIVS + 1),
            ours: Box::new(move || {
                black_box(s.ours.grid_points(black_box(&us), black_box(&vs)));
            }),
            theirs: Box::new(move || {
                black_box(s.theirs.regular_sample_points(GRID_DIVS, GRID_DIVS));
            }),
            mesh: None,
        });
    }
    rows
}

/// Divisions per direction of the grid-evaluation rows: a 201 x 201 grid, about the
/// size of a tessellation's vertex grid on a die-face patch.
pub const GRID_DIVS: usize = 200;

/// Largest parametric deviation `|T(b) - S(uv(b))|` of a mesh from `surface`, sampled on
/// a barycentric lattice of `LATTICE_N + 1` points per side in every triangle (vertices
/// excluded: they lie on the surface). This bounds the distance from the mesh to the
/// surface from above and is the quantity dieface's tessellator guarantees.
pub fn max_deviation(
    surface: &NurbsSurface,
    uv: &[DVec2],
    pos: &[DVec3],
    triangles: impl Iterator<Item = [usize; 3]>,
) -> f64 {
    const LATTICE_N: usize = 8;
    let mut worst: f64 = 0.0;
    for [a, b, c] in triangles {
        for i in 0..=LATTICE_N {
            for j in 0..=(LATTICE_N - i) {
                let k = LATTICE_N - i - j;
                if i == LATTICE_N || j == LATTICE_N || k == LATTICE_N {
                    continue;
                }
                let (ba, bb, bc) = (
                    i as f64 / LATTICE_N as f64,
                    j as f64 / LATTICE_N as f64,
                    k as f64 / LATTICE_N as f64,
                );
                let p = pos[a] * ba + pos[b] * bb + pos[c] * bc;
                let t = uv[a] * ba + uv[b] * bb + uv[c] * bc;
                worst = worst.max((p - surface.point_at(t.x, t.y)).length());
            }
        }
    }
    worst
}

/// dieface's tessellation at [`CHORDAL`] (default angle limit, no edge limit).
pub fn ours_tessellate(s: &NurbsSurface) -> SurfaceMesh {
    tessellate_surface(s, &Tolerance::new(CHORDAL).expect("tolerance"))
        .expect("dieface tessellation")
}

/// Triangle count and measured deviation of a dieface mesh.
pub fn ours_mesh_stats(s: &NurbsSurface, m: &SurfaceMesh) -> (usize, f64) {
    let dev = max_deviation(
        s,
        &m.uv,
        &m.positions,
        m.triangles.iter().map(|t| t.map(|i| i as usize)),
    );
    (m.triangles.len(), dev)
}

/// curvo's tessellation options.
pub type CurvoOptions = AdaptiveTessellationOptions<f64>;

/// Runs curvo's adaptive tessellation.
pub fn theirs_tessellate(
    s: &NurbsSurface3D<f64>,
    o: &CurvoOptions,
) -> curvo::prelude::SurfaceTessellation<f64, nalgebra::U4> {
    s.tessellate(Some(o.clone()))
}

/// Triangle count and measured deviation (against the dieface surface, which agrees
/// with curvo's to 1e-9 mm) of a curvo tessellation.
pub fn theirs_mesh_stats(
    ours: &NurbsSurface,
    theirs: &NurbsSurface3D<f64>,
    o: &CurvoOptions,
) -> (usize, f64) {
    let t = theirs_tessellate(theirs, o);
    let uv: Vec<DVec2> = t.uvs().iter().map(|p| DVec2::new(p.x, p.y)).collect();
    let pos: Vec<DVec3> = t.points().iter().map(dp).collect();
    (
        t.faces().len(),
        max_deviation(ours, &uv, &pos, t.faces().iter().copied()),
    )
}

/// How a curvo setting is driven towards the chordal tolerance.
#[derive(Debug, Clone, Copy)]
pub enum Knob {
    /// Subdivide on the difference of corner normals (curvo's own criterion).
    NormTolerance,
    /// Subdivide on 3-D edge length only (normal criterion switched off).
    MaxEdge,
}

fn options(knob: Knob, value: f64, grid: bool) -> CurvoOptions {
    let o = CurvoOptions::default().with_grid(grid).with_max_depth(16);
    match knob {
        Knob::NormTolerance => o.with_norm_tolerance(value),
        // Unit normals differ by at most 2: a norm tolerance of 3 never divides.
        Knob::MaxEdge => o.with_norm_tolerance(3.0).with_max_edge_length(value),
    }
}

fn describe(knob: Knob, value: f64, grid: bool) -> String {
    let g = if grid { ", grid" } else { "" };
    match knob {
        Knob::NormTolerance => format!("norm_tolerance {value:.4e}{g}"),
        Knob::MaxEdge => format!("max_edge_length {value:.4} mm{g}"),
    }
}

/// Result of tuning curvo for one surface.
pub struct Tuned {
    pub options: CurvoOptions,
    pub settings: String,
    pub triangles: usize,
    pub deviation: f64,
    /// Whether the measured deviation reaches [`CHORDAL`].
    pub reached: bool,
}

/// Finds, for each of curvo's knobs (normal tolerance, max edge length; with and without
/// its `grid` mode), the coarsest setting whose measured deviation is within
/// [`CHORDAL`]: a descending geometric search (factor 0.7) until the tolerance is met,
/// then 8 bisection steps between the last failing and the first passing value. Of the
/// passing candidates, the one that tessellates fastest is returned (best for curvo). If
/// none passes, the most accurate one found.
pub fn tune_curvo(s: &SurfacePair, verbose: bool) -> Tuned {
    let mut candidates: Vec<(CurvoOptions, String, usize, f64)> = Vec::new();
    for grid in [false, true] {
        for (knob, start) in [(Knob::NormTolerance, 0.1), (Knob::MaxEdge, 200.0)] {
            let eval = |v: f64| {
                let o = options(knob, v, grid);
                let (n, d) = theirs_mesh_stats(&s.ours, &s.theirs, &o);
                if verbose {
                    eprintln!(
                        "    tune {}: {:<40} {n:>8} triangles, max deviation {d:.5} mm",
                        s.name,
                        describe(knob, v, grid)
                    );
                }
                (n, d)
            };
            let mut fail = start;
            let (mut n, mut d) = eval(start);
            let mut pass = start;
            let mut steps = 0;
            while d > CHORDAL && steps < 40 && n < 2_000_000 {
                fail = pass;
                pass *= 0.7;
                (n, d) = eval(pass);
                steps += 1;
            }
            if d > CHORDAL {
                candidates.push((options(knob, pass, grid), describe(knob, pass, grid), n, d));
                continue;
            }
            let (mut best_v, mut best_n, mut best_d) = (pass, n, d);
            if fail != pass {
                let (mut lo, mut hi) = (pass.ln(), fail.ln());
                for _ in 0..8 {
                    let mid = 0.5 * (lo + hi);
                    let (n, d) = eval(mid.exp());
                    if d <= CHORDAL {
                        lo = mid;
                        if n < best_n {
                            (best_v, best_n, best_d) = (mid.exp(), n, d);
                        }
                    } else {
                        hi = mid;
                    }
                }
            }
            candidates.push((
                options(knob, best_v, grid),
                describe(knob, best_v, grid),
                best_n,
                best_d,
            ));
        }
    }
    let passing: Vec<_> = candidates.iter().filter(|c| c.3 <= CHORDAL).collect();
    let pick = if passing.is_empty() {
        candidates
            .iter()
            .min_by(|a, b| a.3.total_cmp(&b.3))
            .expect("candidates")
    } else {
        *passing
            .iter()
            .min_by_key(|c| {
                let o = &c.0;
                median_time(
                    || {
                        black_box(theirs_tessellate(&s.theirs, o));
                    },
                    1,
                    5,
                )
            })
            .expect("passing")
    };
    if verbose {
        for c in &candidates {
            eprintln!(
                "    candidate {}: {:<40} {:>8} triangles, {:.5} mm",
                s.name, c.1, c.2, c.3
            );
        }
        eprintln!("    picked {}: {}", s.name, pick.1);
    }
    Tuned {
        options: pick.0.clone(),
        settings: pick.1.clone(),
        triangles: pick.2,
        deviation: pick.3,
        reached: pick.3 <= CHORDAL,
    }
}

/// curvo settings found by [`tune_curvo`] (`cargo run -p dieface-bench --release --bin
/// table -- --tune` repeats the search): the fastest of curvo's knobs whose measured
/// deviation is within [`CHORDAL`]. Rounded to three digits, on the safe side; every run
/// measures the deviation again and reports it.
pub const CURVO_BICUBIC: (Knob, f64, bool) = (Knob::NormTolerance, 2.75e-3, true);
/// See [`CURVO_BICUBIC`].
pub const CURVO_RATIONAL: (Knob, f64, bool) = (Knob::MaxEdge, 2.60, true);

/// curvo's settings for a fixture: tuned now (`tune`), or the recorded ones, measured.
pub fn curvo_settings(s: &SurfacePair, tune: bool, verbose: bool) -> Tuned {
    if tune {
        return tune_curvo(s, verbose);
    }
    let (knob, value, grid) = if s.ours.is_rational() {
        CURVO_RATIONAL
    } else {
        CURVO_BICUBIC
    };
    let o = options(knob, value, grid);
    let (triangles, deviation) = theirs_mesh_stats(&s.ours, &s.theirs, &o);
    Tuned {
        options: o,
        settings: describe(knob, value, grid),
        triangles,
        deviation,
        reached: deviation <= CHORDAL,
    }
}

/// Tessellation rows at [`CHORDAL`], with curvo's settings from [`curvo_settings`].
pub fn tessellation_rows(f: &Fixtures, tune: bool, verbose: bool) -> Vec<Row<'_>> {
    let mut rows = Vec::new();
    for s in [&f.bicubic, &f.rational] {
        let slug = if s.ours.is_rational() {
            "rational"
        } else {
            "bicubic"
        };
        let mesh = ours_tessellate(&s.ours);
        let (ours_triangles, ours_deviation) = ours_mesh_stats(&s.ours, &mesh);
        drop(mesh);
        let tuned = curvo_settings(s, tune, verbose);
        let opts = tuned.options.clone();
        rows.push(Row {
            id: format!("tessellate/{slug}"),
            label: format!("surface tessellation at {CHORDAL} mm, {}", s.name),
            ops: 1,
            ours: Box::new(move || {
                black_box(ours_tessellate(&s.ours));
            }),
            theirs: Box::new(move || {
                black_box(theirs_tessellate(&s.theirs, &opts));
            }),
            mesh: Some(MeshInfo {
                ours_triangles,
                ours_deviation,
                theirs_triangles: tuned.triangles,
                theirs_deviation: tuned.deviation,
                theirs_settings: if tuned.reached {
                    tuned.settings
                } else {
                    format!("{} (NOT within {CHORDAL} mm)", tuned.settings)
                },
            }),
        });
    }
    rows
}

/// The median of `values` (the upper of the middle two for an even count): the figure
/// the benches report of repeated timings.
pub fn median(values: &[f64]) -> f64 {
    let mut sorted = values.to_vec();
    sorted.sort_by(f64::total_cmp);
    sorted[sorted.len() / 2]
}

/// Median over `samples` runs of the time of `reps` calls of `f`, per call.
pub fn median_time(mut f: impl FnMut(), reps: usize, samples: usize) -> Duration {
    let mut times: Vec<Duration> = (0..samples)
        .map(|_| {
            let start = Instant::now();
            for _ in 0..reps {
                f();
            }
            start.elapsed() / reps as u32
        })
        .collect();
    times.sort();
    times[times.len() / 2]
}

/// Writes `mesh` as an OBJ file (`header` first, as comment lines), positions with
/// `decimals` places: how the mesh benches hand a mesh to a peer (MeshLab, at 12 places)
/// and how the examples' meshes are written (as CAD exports them, at 6).
pub fn write_obj(
    mesh: &dieface::geom::mesh::Mesh,
    path: &std::path::Path,
    header: &str,
    decimals: usize,
) {
    let mut text = String::new();
    for line in header.lines() {
        text.push_str(&format!("# {line}\n"));
    }
    for p in mesh.positions() {
        text.push_str(&format!(
            "v {:.d$} {:.d$} {:.d$}\n",
            p.x,
            p.y,
            p.z,
            d = decimals
        ));
    }
    for f in mesh.faces() {
        let ids: Vec<String> = f.indices().iter().map(|i| (i + 1).to_string()).collect();
        text.push_str(&format!("f {}\n", ids.join(" ")));
    }
    if let Some(folder) = path.parent() {
        std::fs::create_dir_all(folder).expect("the OBJ's folder made");
    }
    std::fs::write(path, text).expect("the OBJ written");
}

/// Reads an OBJ file (a peer's result, or the input a filler reads before its run) as
/// one mesh, with dieface's own reader, as `read_obj` in a script reads it.
pub fn read_obj(path: &std::path::Path) -> dieface::geom::mesh::Mesh {
    let bytes = std::fs::read(path).expect("the OBJ read");
    dieface::geom::mesh::obj::parse_obj(&bytes, usize::MAX).expect("an OBJ mesh")
}
