//! Surface to triangles on a structured, knot-aligned tensor grid with verified
//! deviation.
//!
//! The parameter domain is cut by every distinct knot into spans. Each u span gets a
//! number of uniform subdivisions, the same along the whole surface (the largest needed
//! by any v span it meets), and likewise in v. The grid lines therefore run across the
//! whole surface, which makes the mesh watertight by construction: neighbouring cells
//! always share their edge vertices, there are no T-junctions to crack.
//!
//! 1. **Guess.** In every span pair, the second derivatives `|S_uu|`, `|S_uv|`, `|S_vv|`
//!    are sampled on a 3 x 3 grid and bounded (times a safety factor); a triangle of a
//!    `du x dv` cell then deviates by at most
//!    `(M_uu du^2 + 2 M_uv du dv + M_vv dv^2) / 8` from the surface, and `du`, `dv` are
//!    chosen to maximise the cell area under that bound (balancing `M_uu du^2 = M_vv dv^2`).
//!    The turn of the unit normal `|N_u| du` (exact from second derivatives) is kept below
//!    the angle limit, and `|S_u| du` below the edge limit.
//! 2. **Verify.** For every triangle the deviation `T(b) - S(uv(b))` is measured exactly
//!    at its three edge midpoints and its centroid (edge midpoints and the cell centre,
//!    which is the midpoint of both diagonals, are shared between cells and evaluated
//!    once). These four error vectors define the cubic model
//!    `E(b) = 4 sum b_i b_j E_ij + 27 b_0 b_1 b_2 (E_g - 4/9 sum E_ij)`, exact for a
//!    surface that is locally quadratic (plus a cubic bubble), whose largest length over a
//!    25-point barycentric lattice must stay below 97 % of the tolerance. Normals of
//!    neighbouring vertices must not turn by more than the angle limit (along edges
//!    longer than the chordal tolerance: a fold far finer than the tolerance is not
//!    resolved), and edges must not exceed the edge limit.
//! 3. **Fit.** The guess bounds magnitudes, so it is conservative; once it verifies,
//!    every span's count is lowered once by the square root of its measured deviation
//!    ratio (and its angle and edge-length ratios) and the grid is verified again.
//! 4. **Refine.** Every violating cell raises the subdivision count of its u span
//!    column and/or v span row (by the square root of the deviation ratio, in the
//!    direction whose edges carry the error) and the grid is rebuilt, until everything
//!    holds, for at most 16 rounds and [`MAX_VERTICES`] vertices.
//!
//! Each cell is split along its shorter 3-D diagonal. A cell with a collapsed edge (two
//! corners at the same point, as at the apex of a three-sided patch) yields one triangle:
//! grid neighbours that coincide are welded, and triangles that become degenerate are
//! dropped.

use glam::{DVec2, DVec3};
use rayon::prelude::*;

use crate::geom::error::{GeomError, Result};
use crate::geom::knots::KnotVector;
use crate::geom::surface::{Basis, NurbsSurface};
use crate::geom::union_find::UnionFind;

use super::{SurfaceMesh, Tolerance, MAX_VERTICES};
use crate::geom::grid::{BasisTable, Net, Row};

/// Largest modelled triangle deviation accepted, as a fraction of the tolerance; the
/// margin covers what lies beyond the cubic model and between lattice points.
const ACCEPT: f64 = 0.97;
/// Fraction of the tolerance the first guess aims at.
const INITIAL_TARGET: f64 = 0.9;
/// Fraction of the tolerance a refinement step aims at.
const REFINE_TARGET: f64 = 0.88;
/// Fraction of the tolerance the (single) coarsening step aims at.
const COARSEN_TARGET: f64 = 0.93;
/// Factor on the sampled second-derivative and normal-turn bounds of the first guess.
const SAFETY: f64 = 1.2;
/// Samples per direction and span for the first guess.
const GUESS_SAMPLES: usize = 3;
/// Rounds of verification and refinement.
const MAX_ITERATIONS: usize = 16;
/// Largest growth of one span's subdivision count in one round.
const MAX_GROWTH: f64 = 16.0;
/// Points per side of the barycentric lattice on which the deviation model is maximised.
const LATTICE: usize = 6;

/// Approximates `surface` by a triangle mesh within `tol`.
///
/// Every triangle stays within `tol.chordal` of the surface patch it replaces, interior
/// included: measured by the (stronger) parametric deviation `|T(b) - S(uv(b))|`, where
/// `uv(b)` interpolates the corners' parameters, verified at each triangle's edge
/// midpoints and centroid and extrapolated over the triangle by a model exact for
/// locally quadratic surfaces (see the module documentation). Normals of neighbouring
/// vertices turn by at most `tol.angle` (not checked across C0 knots, where the surface
/// has a crease, nor at degenerate points, nor along edges shorter than `tol.chordal`)
/// and edges are at most `tol.max_edge` long.
/// If only the angle or edge limits are still violated after the last refinement round,
/// the mesh is returned anyway.
///
/// The mesh is watertight and wound like `S_u x S_v`; the output is deterministic. Fails
/// with [`GeomError::NoConvergence`] when the chordal tolerance cannot be met within
/// [`MAX_VERTICES`] vertices or 16 refinement rounds, and with [`GeomError::NotFinite`]
/// when the surface evaluates to non-finite points (coordinates near overflow).
pub fn tessellate_surface(surface: &NurbsSurface, tol: &Tolerance) -> Result<SurfaceMesh> {
    tessellate_surface_within(surface, tol, MAX_VERTICES)
}

/// What [`tessellate_surface_within`] names when the grid would need more vertices than
/// it was allowed.
pub const SURFACE_VERTEX_LIMIT: &str =
    "surface tessellation (vertex limit reached: tolerance too fine for the surface)";

/// [`tessellate_surface`] with at most `max_vertices` vertices (and never more than
/// [`MAX_VERTICES`]): the `mesh_vertices` limit, so that a surface that would need
/// millions of triangles fails at once with [`SURFACE_VERTEX_LIMIT`].
pub fn tessellate_surface_within(
    surface: &NurbsSurface,
    tol: &Tolerance,
    max_vertices: usize,
) -> Result<SurfaceMesh> {
    tol.validate()?;
    let max_vertices = max_vertices.clamp(4, MAX_VERTICES);
    let spans_u = Spans::new(surface.knots_u(), surface.degree_u());
    let spans_v = Spans::new(surface.knots_v(), surface.degree_v());
    let (mut counts_u, mut counts_v) = initial_counts(surface, tol, &spans_u, &spans_v);
    let net = Net::new(surface);
    let lattice = lattice();
    let mut worst = 0.0;
    let mut coarsened = false;
    for round in 0..MAX_ITERATIONS {
        let grid = Grid::new(&spans_u, &counts_u, &spans_v, &counts_v, max_vertices).ok_or(
            GeomError::NoConvergence {
                what: SURFACE_VERTEX_LIMIT,
                iterations: round,
                residual: worst,
            },
        )?;
        let pass = verify(surface, &net, &grid, tol, &lattice)?;
        worst = pass.max_deviation;
        let failed = pass
            .request_u
            .iter()
            .chain(&pass.request_v)
            .any(|&f| f > 1.0);
        if !failed && !coarsened {
            // The first guess is conservative (bounds of second-derivative magnitudes);
            // the measured deviations show how much coarser each span may be. Done once,
            // so refinement and coarsening cannot oscillate.
            coarsened = true;
            let changed_u = shrink(&mut counts_u, &pass.fit_u);
            let changed_v = shrink(&mut counts_v, &pass.fit_v);
            if changed_u || changed_v {
                continue;
            }
        }
        if !failed || (!pass.chordal_failed && round + 1 == MAX_ITERATIONS) {
            return Ok(assemble(surface, &grid, pass));
        }
        // A failure after coarsening is repaired by refinement only.
        coarsened = true;
        grow(&mut counts_u, &pass.request_u);
        grow(&mut counts_v, &pass.request_v);
    }
    Err(GeomError::NoConvergence {
        what: "surface tessellation",
        iterations: MAX_ITERATIONS,
        residual: worst,
    })
}

/// The non-empty knot spans of one direction.
struct Spans {
    /// Distinct knots, ends included.
    breaks: Vec<f64>,
    /// Per break: an interior knot of multiplicity >= degree (a possible crease).
    c0: Vec<bool>,
}

impl Spans {
    fn new(knots: &KnotVector, degree: usize) -> Self {
        let distinct = knots.distinct();
        let last = distinct.len().saturating_sub(1);
        let breaks = distinct.iter().map(|&(k, _)| k).collect();
        let c0 = distinct
            .iter()
            .enumerate()
            .map(|(i, &(_, m))| i > 0 && i < last && m >= degree)
            .collect();
        Self { breaks, c0 }
    }

    fn count(&self) -> usize {
        self.breaks.len().saturating_sub(1)
    }

    fn bounds(&self, i: usize) -> (f64, f64) {
        (self.breaks[i], self.breaks[i + 1])
    }
}

/// Subdivision counts per u span and per v span from sampled derivative bounds.
fn initial_counts(
    surface: &NurbsSurface,
    tol: &Tolerance,
    su: &Spans,
    sv: &Spans,
) -> (Vec<usize>, Vec<usize>) {
    let mut counts_u = vec![1; su.count()];
    let mut counts_v = vec![1; sv.count()];
    let budget = 8.0 * INITIAL_TARGET * tol.chordal;
    let s = GUESS_SAMPLES as f64;
    // The samples' basis functions, once per span and sample in each direction (the
    // same numbers as `derivatives` at each sample, without the work per sample).
    let samples = |spans: &Spans, basis: &dyn Fn(f64) -> Basis<3>| -> Vec<Basis<3>> {
        (0..spans.count())
            .flat_map(|i| {
                let (a, b) = spans.bounds(i);
                (0..GUESS_SAMPLES).map(move |k| a + (b - a) * (k as f64 + 0.5) / s)
            })
            .map(basis)
            .collect()
    };
    let basis_u = samples(su, &|u| surface.basis_u::<3>(u));
    let basis_v = samples(sv, &|v| surface.basis_v::<3>(v));
    for (i, count_u) in counts_u.iter_mut().enumerate() {
        let (u0, u1) = su.bounds(i);
        for (j, count_v) in counts_v.iter_mut().enumerate() {
            let (v0, v1) = sv.bounds(j);
            let mut b = Bounds::default();
            for bu in &basis_u[i * GUESS_SAMPLES..(i + 1) * GUESS_SAMPLES] {
                for bv in &basis_v[j * GUESS_SAMPLES..(j + 1) * GUESS_SAMPLES] {
                    b.add(&surface.derivatives_from(bu, bv));
                }
            }
            let (lu, lv) = (u1 - u0, v1 - v0);
            let (mut du, mut dv) =
                cell_size(SAFETY * b.uu, SAFETY * b.uv, SAFETY * b.vv, budget, lu, lv);
            // The angle limit asks for edges no shorter than the chordal tolerance (as
            // verification checks it: see `edge_turn`).
            if b.turn_u > 0.0 {
                let shortest = if b.speed_u > 0.0 {
                    tol.chordal / b.speed_u
                } else {
                    0.0
                };
                du = du.min((tol.angle / (SAFETY * b.turn_u)).max(shortest));
            }
            if b.turn_v > 0.0 {
                let shortest = if b.speed_v > 0.0 {
                    tol.chordal / b.speed_v
                } else {
                    0.0
                };
                dv = dv.min((tol.angle / (SAFETY * b.turn_v)).max(shortest));
            }
            if b.speed_u > 0.0 {
                du = du.min(tol.edge_limit() / (1.05 * b.speed_u));
            }
            if b.speed_v > 0.0 {
                dv = dv.min(tol.edge_limit() / (1.05 * b.speed_v));
            }
            *count_u = (*count_u).max(subdivisions(lu, du));
            *count_v = (*count_v).max(subdivisions(lv, dv));
        }
    }
    (counts_u, counts_v)
}

/// Maxima of derivative magnitudes over the samples of one span pair.
#[derive(Default)]
struct Bounds {
    uu: f64,
    uv: f64,
    vv: f64,
    speed_u: f64,
    speed_v: f64,
    /// Rates of turn of the unit normal per unit parameter, `|N_u|` and `|N_v|`.
    turn_u: f64,
    turn_v: f64,
}

impl Bounds {
    fn add(&mut self, d: &[[DVec3; 3]; 3]) {
        let finite = |x: f64| if x.is_finite() { x } else { 0.0 };
        self.uu = self.uu.max(finite(d[2][0].length()));
        self.uv = self.uv.max(finite(d[1][1].length()));
        self.vv = self.vv.max(finite(d[0][2].length()));
        self.speed_u = self.speed_u.max(finite(d[1][0].length()));
        self.speed_v = self.speed_v.max(finite(d[0][1].length()));
        let n = d[1][0].cross(d[0][1]);
        let len = n.length();
        if len > 1e-12 * d[1][0].length() * d[0][1].length() && len > 0.0 {
            // N = n / |n|, so N_u = (n_u - (n_u . N) N) / |n|, n_u = S_uu x S_v + S_u x S_uv.
            let unit = n / len;
            let n_u = d[2][0].cross(d[0][1]) + d[1][0].cross(d[1][1]);
            let n_v = d[1][1].cross(d[0][1]) + d[1][0].cross(d[0][2]);
            self.turn_u = self
                .turn_u
                .max(finite((n_u - unit * n_u.dot(unit)).length() / len));
            self.turn_v = self
                .turn_v
                .max(finite((n_v - unit * n_v.dot(unit)).length() / len));
        }
    }
}

/// The largest cell `du x dv` (at most `lu x lv`) whose triangles' deviation bound
/// `(a du^2 + 2 b du dv + c dv^2) / 8` stays within `budget / 8`, maximising the area
/// (which balances `a du^2 = c dv^2`).
fn cell_size(a: f64, b: f64, c: f64, budget: f64, lu: f64, lv: f64) -> (f64, f64) {
    let (mut du, mut dv) = if a > 0.0 && c > 0.0 {
        let x = budget / (2.0 + 2.0 * b / (a * c).sqrt());
        ((x / a).sqrt(), (x / c).sqrt())
    } else if a == 0.0 && c == 0.0 {
        if b > 0.0 {
            // Pure twist: only the product du dv is bounded; keep the span's aspect.
            let area = budget / (2.0 * b);
            ((area * lu / lv).sqrt(), (area * lv / lu).sqrt())
        } else {
            (lu, lv)
        }
    } else if c == 0.0 {
        (solve_step(a, b, 0.0, lv, budget), lv)
    } else {
        (lu, solve_step(c, b, 0.0, lu, budget))
    };
    if du > lu {
        du = lu;
        dv = solve_step(c, b, a, lu, budget);
    }
    if dv > lv {
        dv = lv;
        du = solve_step(a, b, c, lv, budget).min(lu);
    }
    (du, dv)
}

/// The positive `x` with `a x^2 + 2 b x y + c y^2 = budget` (infinite when `x` is free).
fn solve_step(a: f64, b: f64, c: f64, y: f64, budget: f64) -> f64 {
    let rest = budget - c * y * y;
    if rest <= 0.0 {
        return 0.0;
    }
    // (-b y + sqrt(b^2 y^2 + a rest)) / a, in the form that stays exact as a -> 0.
    let den = b * y + (b * b * y * y + a * rest).sqrt();
    if den > 0.0 {
        rest / den
    } else {
        f64::INFINITY
    }
}

/// Number of subdivisions of a span of length `len` with steps of at most `step`.
fn subdivisions(len: f64, step: f64) -> usize {
    let n = (len / step).ceil();
    if n.is_nan() || n < 1.0 {
        1
    } else if n >= MAX_VERTICES as f64 {
        MAX_VERTICES
    } else {
        n as usize
    }
}

/// Raises the counts of the spans whose requested growth factor exceeds 1.
fn grow(counts: &mut [usize], requests: &[f64]) {
    for (n, &f) in counts.iter_mut().zip(requests) {
        if f > 1.0 {
            let target = (*n as f64 * f.min(MAX_GROWTH)).ceil();
            let target = if target < MAX_VERTICES as f64 {
                target as usize
            } else {
                MAX_VERTICES
            };
            *n = target.max(*n + 1).min(MAX_VERTICES);
        }
    }
}

/// Lowers the counts of spans whose every constraint holds with room to spare: `fit` is
/// the largest ratio of measured to allowed (in step-length terms) over the span.
/// Returns whether any count changed.
fn shrink(counts: &mut [usize], fit: &[f64]) -> bool {
    let mut changed = false;
    for (n, &f) in counts.iter_mut().zip(fit) {
        if f < 1.0 {
            let target = ((*n as f64) * f.max(0.0)).ceil().max(1.0);
            let target = if target < *n as f64 {
                target as usize
            } else {
                *n
            };
            changed |= target != *n;
            *n = target;
        }
    }
    changed
}

/// The grid parameters of one direction and the points the verification needs.
struct Axis {
    /// Grid line parameters, increasing, knots and ends included.
    params: Vec<f64>,
    /// Per interval: the knot span it lies in.
    span_of: Vec<usize>,
    /// Per interval: its right end is an interior C0 knot (normals there belong to the
    /// next span).
    c0_end: Vec<bool>,
    /// Per interval: midpoint and the points at one and two thirds.
    mid: Vec<f64>,
    third1: Vec<f64>,
    third2: Vec<f64>,
}

impl Axis {
    fn new(spans: &Spans, counts: &[usize]) -> Self {
        let total: usize = counts.iter().sum();
        let mut axis = Self {
            params: Vec::with_capacity(total + 1),
            span_of: Vec::with_capacity(total),
            c0_end: Vec::with_capacity(total),
            mid: Vec::with_capacity(total),
            third1: Vec::with_capacity(total),
            third2: Vec::with_capacity(total),
        };
        for (i, &n) in counts.iter().enumerate() {
            let (a, b) = spans.bounds(i);
            for s in 0..n {
                axis.params.push(a + (b - a) * (s as f64 / n as f64));
                axis.span_of.push(i);
                axis.c0_end.push(s + 1 == n && spans.c0[i + 1]);
            }
        }
        axis.params.push(spans.breaks[spans.count()]);
        for w in axis.params.windows(2) {
            let (a, h) = (w[0], w[1] - w[0]);
            axis.mid.push(a + 0.5 * h);
            axis.third1.push(a + h / 3.0);
            axis.third2.push(a + 2.0 * h / 3.0);
        }
        axis
    }

    fn intervals(&self) -> usize {
        self.span_of.len()
    }
}

/// The tensor grid of one refinement round.
struct Grid {
    u: Axis,
    v: Axis,
}

impl Grid {
    /// `None` when the grid would exceed `max_vertices`.
    fn new(
        su: &Spans,
        cu: &[usize],
        sv: &Spans,
        cv: &[usize],
        max_vertices: usize,
    ) -> Option<Self> {
        let nu = cu.iter().try_fold(1usize, |acc, &n| acc.checked_add(n))?;
        let nv = cv.iter().try_fold(1usize, |acc, &n| acc.checked_add(n))?;
        if nu.checked_mul(nv)? > max_vertices {
            return None;
        }
        Some(Self {
            u: Axis::new(su, cu),
            v: Axis::new(sv, cv),
        })
    }
}

/// Basis tables of one axis at all the parameters the verification uses.
struct Tables {
    grid: BasisTable,
    mid: BasisTable,
    third1: BasisTable,
    third2: BasisTable,
}

impl Tables {
    fn new(knots: &KnotVector, degree: usize, axis: &Axis) -> Self {
        Self {
            grid: BasisTable::new(knots, degree, &axis.params, true),
            mid: BasisTable::new(knots, degree, &axis.mid, false),
            third1: BasisTable::new(knots, degree, &axis.third1, false),
            third2: BasisTable::new(knots, degree, &axis.third2, false),
        }
    }
}

/// The result of one verification round.
struct Pass {
    /// Grid vertex positions, `l * nu + k`.
    positions: Vec<DVec3>,
    /// Unit normals, or zero where the surface normal is undefined.
    normals: Vec<DVec3>,
    /// Per cell: split along the `(0,0)-(1,1)` diagonal (else `(1,0)-(0,1)`).
    diagonal: Vec<bool>,
    /// Requested growth factor per u span and per v span (1 = fine).
    request_u: Vec<f64>,
    request_v: Vec<f64>,
    /// Per u span and per v span: the largest ratio, over its cells and edges, of the
    /// measured deviation, normal turn and edge length to what is allowed, in step-length
    /// terms (square root for the deviation). Below 1 the span could be coarser.
    fit_u: Vec<f64>,
    fit_v: Vec<f64>,
    /// Per u span and per v span: extremes of the grid edges' normal turn and length.
    edges_u: Vec<EdgeExtremes>,
    edges_v: Vec<EdgeExtremes>,
    /// Whether some triangle violates the chordal tolerance.
    chordal_failed: bool,
    /// Largest modelled deviation of any triangle (an upper estimate where it is small).
    max_deviation: f64,
}

/// Evaluates the grid, picks the diagonals and checks every cell.
///
/// The rows of cells are checked in bands side by side (see [`verify_rows`]); every
/// figure of a pass is a largest or smallest value or a flag, so the bands' passes
/// joined in order are the pass of the whole grid, bit for bit, however many bands.
fn verify(
    surface: &NurbsSurface,
    net: &Net,
    grid: &Grid,
    tol: &Tolerance,
    lattice: &[[f64; 4]],
) -> Result<Pass> {
    let tu = Tables::new(surface.knots_u(), surface.degree_u(), &grid.u);
    let tv = Tables::new(surface.knots_v(), surface.degree_v(), &grid.v);
    let cv = grid.v.intervals();
    let bands = (tu.grid.len() * cv / ROWS_BAND_VERTICES)
        .clamp(1, rayon::current_num_threads().max(1))
        .min(cv.max(1));
    let bounds: Vec<(usize, usize)> = (0..bands)
        .map(|b| (cv * b / bands, cv * (b + 1) / bands))
        .collect();
    let tables = (&tu, &tv);
    let mut passes = bounds
        .par_iter()
        .map(|&rows| verify_rows(surface, net, grid, tol, lattice, tables, rows))
        .collect::<Vec<_>>()
        .into_iter();
    let mut pass = passes.next().expect("at least one band")?;
    let nu = tu.grid.len();
    for band in passes {
        pass.join(band?, nu);
    }
    for (i, &edges) in pass.edges_u.iter().enumerate() {
        edge_limits(&mut pass.request_u[i], &mut pass.fit_u[i], edges, tol);
    }
    for (j, &edges) in pass.edges_v.iter().enumerate() {
        edge_limits(&mut pass.request_v[j], &mut pass.fit_v[j], edges, tol);
    }
    Ok(pass)
}

/// Below this many grid vertices per band, the cells are checked in one band: a small
/// grid is done before another thread would start.
const ROWS_BAND_VERTICES: usize = 20_000;

impl Pass {
    /// Joins the pass of the next band of rows (whose first vertex row is this pass's
    /// last, evaluated again) onto this one.
    fn join(&mut self, next: Pass, nu: usize) {
        self.positions.extend_from_slice(&next.positions[nu..]);
        self.normals.extend_from_slice(&next.normals[nu..]);
        self.diagonal.extend(next.diagonal);
        let most = |a: &mut Vec<f64>, b: Vec<f64>| {
            for (x, y) in a.iter_mut().zip(b) {
                bump(x, y);
            }
        };
        most(&mut self.request_u, next.request_u);
        most(&mut self.request_v, next.request_v);
        most(&mut self.fit_u, next.fit_u);
        most(&mut self.fit_v, next.fit_v);
        for (x, y) in self.edges_u.iter_mut().zip(next.edges_u) {
            x.add(y.min_cos, y.max_len);
        }
        for (x, y) in self.edges_v.iter_mut().zip(next.edges_v) {
            x.add(y.min_cos, y.max_len);
        }
        self.chordal_failed |= next.chordal_failed;
        self.max_deviation = f64::max(self.max_deviation, next.max_deviation);
    }
}

/// [`verify`] of the cells in rows `first..end` (vertex rows `first..=end`), as a pass
/// of its own whose positions start at vertex row `first`; the span edge limits are left
/// to the caller.
fn verify_rows(
    surface: &NurbsSurface,
    net: &Net,
    grid: &Grid,
    tol: &Tolerance,
    lattice: &[[f64; 4]],
    (tu, tv): (&Tables, &Tables),
    (first, end): (usize, usize),
) -> Result<Pass> {
    let nu = tu.grid.len();
    let cu = grid.u.intervals();
    let rows = end - first;
    let mut pass = Pass {
        positions: Vec::with_capacity(nu * (rows + 1)),
        normals: Vec::with_capacity(nu * (rows + 1)),
        diagonal: Vec::with_capacity(cu * rows),
        request_u: vec![1.0; grid.u.span_of.last().map_or(0, |&s| s + 1)],
        request_v: vec![1.0; grid.v.span_of.last().map_or(0, |&s| s + 1)],
        fit_u: vec![0.0; grid.u.span_of.last().map_or(0, |&s| s + 1)],
        fit_v: vec![0.0; grid.v.span_of.last().map_or(0, |&s| s + 1)],
        edges_u: vec![EdgeExtremes::NONE; grid.u.span_of.last().map_or(0, |&s| s + 1)],
        edges_v: vec![EdgeExtremes::NONE; grid.v.span_of.last().map_or(0, |&s| s + 1)],
        chordal_failed: false,
        max_deviation: 0.0,
    };
    let accept = ACCEPT * tol.chordal;
    let max_edge = tol.edge_limit();
    let floor = speed_floor(surface);
    let mut row = Row::new();
    let mut row_third1 = Row::new();
    let mut row_third2 = Row::new();
    // u-edge midpoints on the cell row's bottom and top grid lines.
    let mut mids_bottom = Vec::with_capacity(cu);
    let mut mids_top = Vec::with_capacity(cu);
    // On the v midline of the cell row: v-edge midpoints (at grid u) and cell centres.
    let mut mids_v = Vec::with_capacity(nu);
    let mut centres = Vec::with_capacity(cu);

    vertex_row(
        &mut pass,
        &mut mids_bottom,
        &mut row,
        net,
        (tu, tv),
        floor,
        first,
    )?;
    check_u_edges(&mut pass, grid, 0, nu, tol.chordal);
    for l in first..end {
        // Vertex rows are stored from `first`: row `l` starts at `(l - first) * nu`.
        let local = l - first;
        vertex_row(
            &mut pass,
            &mut mids_top,
            &mut row,
            net,
            (tu, tv),
            floor,
            l + 1,
        )?;
        check_u_edges(&mut pass, grid, local + 1, nu, tol.chordal);
        let span_v = grid.v.span_of[l];
        // v edges between rows l and l + 1.
        for k in 0..nu {
            let (a, b) = (local * nu + k, (local + 1) * nu + k);
            let len = pass.positions[a].distance(pass.positions[b]);
            let cos = edge_turn(&pass, (a, b), len, grid.v.c0_end[l], tol.chordal);
            pass.edges_v[span_v].add(cos, len);
        }
        row.fill(net, &tv.mid, l, false);
        mids_v.clear();
        mids_v.extend((0..nu).map(|k| row.point(&tu.grid, k)));
        centres.clear();
        centres.extend((0..cu).map(|k| row.point(&tu.mid, k)));
        row_third1.fill(net, &tv.third1, l, false);
        row_third2.fill(net, &tv.third2, l, false);
        for k in 0..cu {
            let (i00, i10) = (local * nu + k, local * nu + k + 1);
            let (i01, i11) = (i00 + nu, i10 + nu);
            let p = &pass.positions;
            let (p00, p10, p01, p11) = (p[i00], p[i10], p[i01], p[i11]);
            let e_bottom = (p00 + p10) * 0.5 - mids_bottom[k];
            let e_top = (p01 + p11) * 0.5 - mids_top[k];
            let e_left = (p00 + p01) * 0.5 - mids_v[k];
            let e_right = (p10 + p11) * 0.5 - mids_v[k + 1];
            let (d0, d1) = (p00.distance(p11), p10.distance(p01));
            let main = d0 <= d1;
            pass.diagonal.push(main);
            let dev = if main {
                // Triangles (00, 10, 11) and (00, 11, 01).
                let e_diag = (p00 + p11) * 0.5 - centres[k];
                let g1 = (p00 + p10 + p11) / 3.0 - row_third1.point(&tu.third2, k);
                let g2 = (p00 + p11 + p01) / 3.0 - row_third2.point(&tu.third1, k);
                triangle_deviation(e_bottom, e_right, e_diag, g1, lattice, accept).max(
                    triangle_deviation(e_diag, e_top, e_left, g2, lattice, accept),
                )
            } else {
                // Triangles (00, 10, 01) and (10, 11, 01).
                let e_diag = (p10 + p01) * 0.5 - centres[k];
                let g1 = (p00 + p10 + p01) / 3.0 - row_third1.point(&tu.third1, k);
                let g2 = (p10 + p11 + p01) / 3.0 - row_third2.point(&tu.third2, k);
                triangle_deviation(e_bottom, e_diag, e_left, g1, lattice, accept).max(
                    triangle_deviation(e_right, e_top, e_diag, g2, lattice, accept),
                )
            };
            if dev.is_nan() {
                return Err(GeomError::NotFinite {
                    what: "surface point",
                });
            }
            pass.max_deviation = f64::max(pass.max_deviation, dev);
            let span_u = grid.u.span_of[k];
            let fit = (dev / (COARSEN_TARGET * tol.chordal)).sqrt();
            bump(&mut pass.fit_u[span_u], fit);
            bump(&mut pass.fit_v[span_v], fit);
            if dev > accept {
                pass.chordal_failed = true;
                let s = (dev / (REFINE_TARGET * tol.chordal)).sqrt();
                let e_u = e_bottom.length().max(e_top.length());
                let e_v = e_left.length().max(e_right.length());
                let share_u = if e_u + e_v > 0.0 {
                    e_u / (e_u + e_v)
                } else {
                    0.5
                };
                if share_u > 0.15 {
                    bump(&mut pass.request_u[span_u], s);
                }
                if share_u < 0.85 {
                    bump(&mut pass.request_v[span_v], s);
                }
            }
            let diagonal = d0.min(d1);
            bump(&mut pass.fit_u[span_u], 1.05 * diagonal / max_edge);
            bump(&mut pass.fit_v[span_v], 1.05 * diagonal / max_edge);
            if diagonal > max_edge {
                let f = 1.01 * diagonal / max_edge;
                if p00.distance(p10) >= p00.distance(p01) {
                    bump(&mut pass.request_u[span_u], f);
                } else {
                    bump(&mut pass.request_v[span_v], f);
                }
            }
        }
        std::mem::swap(&mut mids_bottom, &mut mids_top);
    }
    Ok(pass)
}

/// Speeds `|S_u|`, `|S_v|` below which a point counts as degenerate (a collapsed edge):
/// 1e-10 of the surface's size over the domain length. At a collapsed edge the tangent
/// along it is rounding noise, about 1e-16 of the size; a relative test of `S_u x S_v`
/// against `|S_u| |S_v|` would take that noise for a direction.
fn speed_floor(surface: &NurbsSurface) -> (f64, f64) {
    let size = 1.0 + surface.control_scale();
    let ((u0, u1), (v0, v1)) = (surface.domain_u(), surface.domain_v());
    (1e-10 * size / (u1 - u0), 1e-10 * size / (v1 - v0))
}

/// Evaluates grid row `l`: vertices with normals into `pass`, u-edge midpoints into `mids`.
fn vertex_row(
    pass: &mut Pass,
    mids: &mut Vec<DVec3>,
    row: &mut Row,
    net: &Net,
    (tu, tv): (&Tables, &Tables),
    floor: (f64, f64),
    l: usize,
) -> Result<()> {
    row.fill(net, &tv.grid, l, true);
    for k in 0..tu.grid.len() {
        let (s, su, sv) = row.point_and_tangents(&tu.grid, k);
        if !s.is_finite() {
            return Err(GeomError::NotFinite {
                what: "surface point",
            });
        }
        pass.positions.push(s);
        let degenerate = su.length() <= floor.0 || sv.length() <= floor.1;
        pass.normals.push(if degenerate {
            DVec3::ZERO
        } else {
            unit_normal(su, sv)
        });
    }
    mids.clear();
    mids.extend((0..tu.mid.len()).map(|k| row.point(&tu.mid, k)));
    Ok(())
}

/// Angle and edge-length checks of the u edges on grid row `l`. The normal's turn along
/// an edge shorter than `resolution` (the chordal tolerance) is not limited: see
/// [`edge_turn`].
fn check_u_edges(pass: &mut Pass, grid: &Grid, l: usize, nu: usize, resolution: f64) {
    for k in 0..nu - 1 {
        let (a, b) = (l * nu + k, l * nu + k + 1);
        let len = pass.positions[a].distance(pass.positions[b]);
        let cos = edge_turn(pass, (a, b), len, grid.u.c0_end[k], resolution);
        pass.edges_u[grid.u.span_of[k]].add(cos, len);
    }
}

/// The cosine of the normal's turn along the grid edge `a b` of length `len` for the
/// angle limit: 1 (no turn) across a C0 knot (a crease kept as drawn) and along an
/// edge shorter than `resolution`, the chordal tolerance. A fold or a pinch of a radius
/// far below the tolerance (the tapered end of a bead, say) turns the normal within a
/// hair's breadth; resolving it to the angle limit asked for millions of vertices for
/// a detail the tolerance says is not to be drawn.
fn edge_turn(pass: &Pass, (a, b): (usize, usize), len: f64, c0: bool, resolution: f64) -> f64 {
    if c0 || len < resolution {
        1.0
    } else {
        cos_turn(pass.normals[a], pass.normals[b])
    }
}

/// The extremes over the grid edges of one span: the smallest cosine of the normal turn
/// and the longest edge.
#[derive(Clone, Copy)]
struct EdgeExtremes {
    min_cos: f64,
    max_len: f64,
}

impl EdgeExtremes {
    const NONE: Self = Self {
        min_cos: 1.0,
        max_len: 0.0,
    };

    fn add(&mut self, cos: f64, len: f64) {
        self.min_cos = self.min_cos.min(cos);
        self.max_len = self.max_len.max(len);
    }
}

/// Turns a span's edge extremes into growth requests (when a limit is violated) and
/// fit ratios (how close to the limits it is in any case, with a margin for coarsening).
fn edge_limits(request: &mut f64, fit: &mut f64, edges: EdgeExtremes, tol: &Tolerance) {
    let turn = edges.min_cos.clamp(-1.0, 1.0).acos();
    let (turn_ratio, len_ratio) = (turn / tol.angle, edges.max_len / tol.edge_limit());
    if turn_ratio > 1.0 {
        bump(request, 1.05 * turn_ratio);
    }
    if len_ratio > 1.0 {
        bump(request, 1.01 * len_ratio);
    }
    bump(fit, 1.05 * turn_ratio.max(len_ratio));
}

fn bump(request: &mut f64, f: f64) {
    if f > *request {
        *request = f;
    }
}

/// `S_u x S_v` normalised, or zero at a degenerate point (the criterion of
/// [`NurbsSurface::normal`]).
fn unit_normal(su: DVec3, sv: DVec3) -> DVec3 {
    let n = su.cross(sv);
    let len = n.length();
    if len > 1e-14 * su.length() * sv.length() && len > 0.0 && len.is_finite() {
        n / len
    } else {
        DVec3::ZERO
    }
}

/// Cosine of the angle between two unit normals; 1 (no turn) when either is undefined
/// (zero).
fn cos_turn(a: DVec3, b: DVec3) -> f64 {
    if a == DVec3::ZERO || b == DVec3::ZERO {
        return 1.0;
    }
    a.dot(b)
}

/// Barycentric weights `(4 b0 b1, 4 b1 b2, 4 b2 b0, 27 b0 b1 b2)` of the lattice points
/// (corners excluded) on which the deviation model is maximised.
fn lattice() -> Vec<[f64; 4]> {
    let n = LATTICE;
    let mut out = Vec::with_capacity((n + 1) * (n + 2) / 2);
    for i in 0..=n {
        for j in 0..=n - i {
            let k = n - i - j;
            if i == n || j == n || k == n {
                continue;
            }
            let (b0, b1, b2) = (
                i as f64 / n as f64,
                j as f64 / n as f64,
                k as f64 / n as f64,
            );
            out.push([
                4.0 * b0 * b1,
                4.0 * b1 * b2,
                4.0 * b2 * b0,
                27.0 * b0 * b1 * b2,
            ]);
        }
    }
    out
}

/// Largest deviation of a triangle by the cubic model through its edge-midpoint errors
/// `e01`, `e12`, `e20` and centroid error `eg`. Cheaper upper bounds of that maximum are
/// returned instead when they already stay below `accept` (half of it for the coarsest).
fn triangle_deviation(
    e01: DVec3,
    e12: DVec3,
    e20: DVec3,
    eg: DVec3,
    lattice: &[[f64; 4]],
    accept: f64,
) -> f64 {
    let bubble = eg - (e01 + e12 + e20) * (4.0 / 9.0);
    let lengths = [e01.length(), e12.length(), e20.length(), bubble.length()];
    let bound = 4.0 / 3.0 * lengths[0].max(lengths[1]).max(lengths[2]) + lengths[3];
    if bound <= 0.5 * accept || bound.is_nan() {
        return bound;
    }
    // The triangle inequality on the lattice: exact when the error vectors are parallel
    // (a cylinder), cheap (scalars only), and enough to accept most triangles.
    let mut scalar: f64 = 0.0;
    for w in lattice {
        scalar = scalar
            .max(w[0] * lengths[0] + w[1] * lengths[1] + w[2] * lengths[2] + w[3] * lengths[3]);
    }
    if scalar <= accept {
        return scalar;
    }
    let mut worst2: f64 = 0.0;
    for w in lattice {
        let e = e01 * w[0] + e12 * w[1] + e20 * w[2] + bubble * w[3];
        worst2 = worst2.max(e.length_squared());
    }
    worst2.sqrt()
}

/// Builds the output mesh: welds coincident grid neighbours, emits the non-degenerate
/// triangles and fills in normals where the surface has none.
fn assemble(surface: &NurbsSurface, grid: &Grid, pass: Pass) -> SurfaceMesh {
    let nu = grid.u.params.len();
    let nv = grid.v.params.len();
    let count = nu * nv;
    let eps = 1e-12 * (1.0 + surface.control_scale());
    let pos = &pass.positions;

    // Grid neighbours whose positions coincide, welded; the root is the smallest index.
    let mut welds = UnionFind::new(count);
    for l in 0..nv {
        for k in 0..nu {
            let a = l * nu + k;
            if k + 1 < nu && pos[a].distance(pos[a + 1]) <= eps {
                welds.union(a, a + 1);
            }
            if l + 1 < nv && pos[a].distance(pos[a + nu]) <= eps {
                welds.union(a, a + nu);
            }
        }
    }

    let mut mesh = SurfaceMesh::default();
    let mut index = vec![0u32; count];
    for i in 0..count {
        let root = welds.find(i);
        if root == i {
            // Fits: the grid has at most MAX_VERTICES < u32::MAX vertices.
            index[i] = mesh.positions.len() as u32;
            let (k, l) = (i % nu, i / nu);
            mesh.uv.push(DVec2::new(grid.u.params[k], grid.v.params[l]));
            mesh.positions.push(pos[i]);
            mesh.normals.push(pass.normals[i]);
        } else {
            index[i] = index[root];
        }
    }

    mesh.triangles.reserve(2 * (nu - 1) * (nv - 1));
    for l in 0..nv - 1 {
        for k in 0..nu - 1 {
            let i00 = l * nu + k;
            let (a, b, c, d) = (
                index[i00],
                index[i00 + 1],
                index[i00 + nu],
                index[i00 + nu + 1],
            );
            let pair = if pass.diagonal[l * (nu - 1) + k] {
                [[a, b, d], [a, d, c]]
            } else {
                [[a, b, c], [b, d, c]]
            };
            for t in pair {
                if t[0] != t[1] && t[1] != t[2] && t[2] != t[0] {
                    mesh.triangles.push(t);
                }
            }
        }
    }

    fill_missing_normals(surface, &mut mesh);
    mesh
}

/// Gives every vertex without a surface normal (a collapsed edge, a cusp) the
/// area-weighted normal of its triangles, or failing that the surface normal at a
/// parameter nudged into the domain.
fn fill_missing_normals(surface: &NurbsSurface, mesh: &mut SurfaceMesh) {
    if !mesh.normals.contains(&DVec3::ZERO) {
        return;
    }
    let mut sums = vec![DVec3::ZERO; mesh.positions.len()];
    for t in &mesh.triangles {
        let [a, b, c] = t.map(|i| i as usize);
        if mesh.normals[a] != DVec3::ZERO
            && mesh.normals[b] != DVec3::ZERO
            && mesh.normals[c] != DVec3::ZERO
        {
            continue;
        }
        let n =
            (mesh.positions[b] - mesh.positions[a]).cross(mesh.positions[c] - mesh.positions[a]);
        for i in [a, b, c] {
            sums[i] += n;
        }
    }
    let (u0, u1) = surface.domain_u();
    let (v0, v1) = surface.domain_v();
    for (i, normal) in mesh.normals.iter_mut().enumerate() {
        if *normal != DVec3::ZERO {
            continue;
        }
        if let Some(n) = sums[i].try_normalize() {
            *normal = n;
            continue;
        }
        let uv = mesh.uv[i];
        let centre = DVec2::new(0.5 * (u0 + u1), 0.5 * (v0 + v1));
        let nudged = uv + (centre - uv) * 1e-6;
        *normal = surface.normal(nudged.x, nudged.y).unwrap_or(DVec3::Z);
    }
}
