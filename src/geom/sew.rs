//! Sewing faces into one shell with shared edges: the topology a STEP file carries.
//!
//! Each face brings its boundary as curves in loop order, counter-clockwise around its
//! normal `S_u x S_v`: an untrimmed patch its four iso-curve edges (those shorter than
//! the tolerance dropped: the collapsed side of a three-sided patch), a trimmed face
//! its outer loop. Then, without knowing which feature a face came from:
//!
//! 1. the curves' end points are merged into vertices (within the tolerance);
//! 2. every boundary curve is split at each vertex of another curve that lies on it
//!    (within the tolerance, away from its ends): a binder side's inner edge at the
//!    step-draw patch corners along it, the product outline at the step draw's;
//! 3. pieces with the same end vertices that coincide (sampled interior points within
//!    the tolerance of the other piece) become one edge, used by both faces in opposite
//!    directions. The edge keeps the first face's piece as its curve.
//!
//! Pieces that match nothing stay free edges (the binder's outer edge). A piece that
//! would be a third use of an edge stays free too, so the shell is never non-manifold.

use glam::DVec3;
use rayon::prelude::*;

use super::curve::Curve3;
use super::error::Result;
use super::inversion::{closest_point_on_curve, project_to_curve_locally};
use super::surface::{Direction, NurbsSurface};
use super::trimmed::TrimmedSurface;

/// The sewing tolerance a die face is written with (mm): the step draw's opening edge
/// lies within 0.005 mm of the binder's inner edge, and everything else meets far
/// closer.
pub const DIE_FACE_TOLERANCE: f64 = 0.01;

/// A face to sew: an untrimmed patch or a trimmed face, with a name.
#[derive(Debug, Clone, PartialEq)]
pub struct Face {
    /// The face's name (`binder/front`, `fender`).
    pub name: String,
    /// The face's geometry.
    pub shape: Shape,
}

/// What a face is cut from its surface.
#[derive(Debug, Clone, PartialEq)]
pub enum Shape {
    /// The whole patch: bounded by its four iso-curve edges.
    Patch(NurbsSurface),
    /// A surface trimmed at its outer loop.
    Trimmed(TrimmedSurface),
}

impl Face {
    /// The underlying (untrimmed) surface.
    pub fn surface(&self) -> &NurbsSurface {
        match &self.shape {
            Shape::Patch(s) => s,
            Shape::Trimmed(t) => t.surface(),
        }
    }

    /// The face's area (mm²).
    pub fn area(&self) -> f64 {
        match &self.shape {
            Shape::Patch(s) => s.area(),
            Shape::Trimmed(t) => t.area(),
        }
    }

    /// The boundary curves in loop order, counter-clockwise around `S_u x S_v`, those
    /// shorter than `tol` dropped.
    pub fn boundary(&self, tol: f64) -> Vec<Curve3> {
        match &self.shape {
            Shape::Patch(s) => {
                let (u0, u1) = s.domain_u();
                let (v0, v1) = s.domain_v();
                [
                    s.iso_curve(Direction::V, v0),
                    s.iso_curve(Direction::U, u1),
                    s.iso_curve(Direction::V, v1).reversed(),
                    s.iso_curve(Direction::U, u0).reversed(),
                ]
                .into_iter()
                .filter(|c| c.length() > tol)
                .collect()
            }
            Shape::Trimmed(t) => {
                let c = t.outer().curve();
                vec![if t.outer().counter_clockwise() {
                    c.clone()
                } else {
                    c.reversed()
                }]
            }
        }
    }
}

/// An edge of the shell: a curve from vertex `start` to vertex `end`.
#[derive(Debug, Clone, PartialEq)]
pub struct Edge {
    /// The edge's curve, running from `start` to `end`.
    pub curve: Curve3,
    /// Index of the start vertex.
    pub start: usize,
    /// Index of the end vertex.
    pub end: usize,
}

/// A sewn face: the face and its boundary as edges in loop order, each with whether
/// the loop runs along the edge's curve (`true`) or against it. The outer loop runs
/// counter-clockwise around the face's normal, which is the surface's `S_u x S_v`, or
/// its opposite when `reversed`; its holes run clockwise, so the face always lies to
/// the left.
#[derive(Debug, Clone, PartialEq)]
pub struct SewnFace {
    /// The face.
    pub face: Face,
    /// The outer loop: `(edge index, same direction)` in loop order.
    pub bound: Vec<(usize, bool)>,
    /// The inner loops, the same way: none from [`sew`]; a face imprinted into the
    /// shell ([`super::imprint`], a draw bead on the binder) leaves one where it lies
    /// inside a face.
    pub holes: Vec<Vec<(usize, bool)>>,
    /// Whether the face's normal is turned against its surface's, so that the shell
    /// is oriented consistently (every shared edge used in opposite directions).
    pub reversed: bool,
}

/// Faces sewn along shared edges.
#[derive(Debug, Clone, PartialEq)]
pub struct Shell {
    /// Vertex positions.
    pub vertices: Vec<DVec3>,
    /// Edges, each used by one face (a free edge) or two (a shared one).
    pub edges: Vec<Edge>,
    /// The faces in input order.
    pub faces: Vec<SewnFace>,
}

impl SewnFace {
    /// Every loop's edges, the outer loop first, then the holes.
    pub fn loop_edges(&self) -> impl Iterator<Item = &(usize, bool)> {
        self.bound.iter().chain(self.holes.iter().flatten())
    }
}

impl Shell {
    /// How many faces use each edge.
    pub fn edge_uses(&self) -> Vec<usize> {
        let mut uses = vec![0; self.edges.len()];
        for f in &self.faces {
            for &(e, _) in f.loop_edges() {
                uses[e] += 1;
            }
        }
        uses
    }

    /// The edges used by one face only: the shell's free boundary.
    pub fn free_edges(&self) -> Vec<usize> {
        let uses = self.edge_uses();
        (0..self.edges.len()).filter(|&e| uses[e] == 1).collect()
    }

    /// The total area of the faces (mm²).
    pub fn area(&self) -> f64 {
        self.faces.iter().map(|f| f.face.area()).sum()
    }
}

/// A piece of a face's boundary between two vertices.
struct Piece {
    curve: Curve3,
    start: usize,
    end: usize,
}

/// Sews `faces` into a shell: vertices merged, boundary curves split at each other's
/// vertices, and coinciding pieces shared, all within `tol` (mm).
///
/// Errors: the kernel's point inversion failing on a boundary curve.
pub fn sew(faces: Vec<Face>, tol: f64) -> Result<Shell> {
    let boundaries: Vec<Vec<Curve3>> = faces.par_iter().map(|f| f.boundary(tol)).collect();
    // 1. Vertices.
    let mut vertices: Vec<DVec3> = Vec::new();
    let vertex = |p: DVec3, vertices: &mut Vec<DVec3>| -> usize {
        match vertices.iter().position(|v| v.distance(p) <= tol) {
            Some(i) => i,
            None => {
                vertices.push(p);
                vertices.len() - 1
            }
        }
    };
    let mut ends: Vec<Vec<(usize, usize)>> = Vec::with_capacity(boundaries.len());
    for b in &boundaries {
        let e = b
            .iter()
            .map(|c| {
                (
                    vertex(c.start_point(), &mut vertices),
                    vertex(c.end_point(), &mut vertices),
                )
            })
            .collect();
        ends.push(e);
    }
    // 2. Split every curve at the vertices on it: each face's on its own, side by side,
    // kept in face order (and the first face's error in that order, as one by one).
    let pieces: Vec<Result<Vec<Piece>>> = boundaries
        .par_iter()
        .zip(&ends)
        .map(|(b, e)| split_at_vertices(b, e, &vertices, tol))
        .collect();
    let pieces: Vec<Vec<Piece>> = pieces.into_iter().collect::<Result<_>>()?;
    // 3. Share coinciding pieces.
    let mut edges: Vec<Edge> = Vec::new();
    let mut uses: Vec<usize> = Vec::new();
    let mut sewn = Vec::with_capacity(faces.len());
    for (face, face_pieces) in faces.into_iter().zip(pieces) {
        let mut bound = Vec::with_capacity(face_pieces.len());
        for piece in face_pieces {
            let found = edges.iter().enumerate().find_map(|(k, e)| {
                if uses[k] != 1 {
                    return None;
                }
                let same_ends = (e.start == piece.start && e.end == piece.end)
                    || (e.start == piece.end && e.end == piece.start);
                if !same_ends {
                    return None;
                }
                coincide(&e.curve, &piece.curve, tol).map(|forward| (k, forward))
            });
            match found {
                Some((k, forward)) => {
                    uses[k] += 1;
                    bound.push((k, forward));
                }
                None => {
                    edges.push(Edge {
                        curve: piece.curve,
                        start: piece.start,
                        end: piece.end,
                    });
                    uses.push(1);
                    bound.push((edges.len() - 1, true));
                }
            }
        }
        sewn.push(SewnFace {
            face,
            bound,
            holes: Vec::new(),
            reversed: false,
        });
    }
    orient(&mut sewn, edges.len());
    Ok(Shell {
        vertices,
        edges,
        faces: sewn,
    })
}

/// A face's boundary curves `b` (with their end vertices `e`) split at every other
/// vertex of `vertices` lying on them within `tol`, in order along each curve.
fn split_at_vertices(
    b: &[Curve3],
    e: &[(usize, usize)],
    vertices: &[DVec3],
    tol: f64,
) -> Result<Vec<Piece>> {
    let mut face_pieces = Vec::new();
    for (curve, &(s, t)) in b.iter().zip(e) {
        let mut cuts: Vec<(f64, usize)> = Vec::new();
        let (lo, hi) = bounds(curve);
        for (i, &p) in vertices.iter().enumerate() {
            if i == s || i == t || !inside_box(p, lo, hi, tol) {
                continue;
            }
            let cp = closest_point_on_curve(curve, p)?;
            let clear_of_ends = cp.point.distance(curve.start_point()) > tol
                && cp.point.distance(curve.end_point()) > tol;
            if cp.distance <= tol && clear_of_ends {
                cuts.push((cp.t, i));
            }
        }
        cuts.sort_by(|a, b| a.0.total_cmp(&b.0));
        let mut rest = curve.clone();
        let mut from = s;
        for (t_cut, v) in cuts {
            let (a, b) = rest.split_at(t_cut)?;
            face_pieces.push(Piece {
                curve: a,
                start: from,
                end: v,
            });
            rest = b;
            from = v;
        }
        face_pieces.push(Piece {
            curve: rest,
            start: from,
            end: t,
        });
    }
    Ok(face_pieces)
}

/// Turns faces so that every shared edge is used in opposite directions: the first
/// face of each connected group keeps its orientation, each neighbour follows across
/// the edges they share. (On a non-orientable group the later face keeps the first
/// orientation found.)
fn orient(faces: &mut [SewnFace], edge_count: usize) {
    let mut users: Vec<Vec<(usize, bool)>> = vec![Vec::new(); edge_count];
    for (i, f) in faces.iter().enumerate() {
        for &(e, d) in f.loop_edges() {
            users[e].push((i, d));
        }
    }
    let mut flip: Vec<Option<bool>> = vec![None; faces.len()];
    for start in 0..faces.len() {
        if flip[start].is_some() {
            continue;
        }
        flip[start] = Some(false);
        let mut stack = vec![start];
        while let Some(f) = stack.pop() {
            let flip_f = flip[f].unwrap_or(false);
            for &(e, d) in faces[f].loop_edges() {
                for &(g, dg) in &users[e] {
                    if g != f && flip[g].is_none() {
                        // g is used the way f effectively runs: turn it.
                        flip[g] = Some((d ^ flip_f) == dg);
                        stack.push(g);
                    }
                }
            }
        }
    }
    for (f, flipped) in faces.iter_mut().zip(flip) {
        if flipped == Some(true) {
            for l in std::iter::once(&mut f.bound).chain(&mut f.holes) {
                l.reverse();
                for b in l.iter_mut() {
                    b.1 = !b.1;
                }
            }
            f.reversed = true;
        }
    }
}

/// Whether `b` runs along `a` within `tol` (interior samples of `b` near `a`): `Some`
/// with whether they run the same way, `None` when they do not coincide.
///
/// The first sample is found on `a` by the global search; each next one by Newton from
/// the foot of the one before (the samples march along `a` when the curves coincide),
/// and by the global search again only where that foot is farther than `tol`. A foot
/// found locally lies on `a`, so `a` is at least that near: the answer is the global
/// search's, without searching every span of a long outline for each sample (which made
/// most of sewing the die face).
fn coincide(a: &Curve3, b: &Curve3, tol: f64) -> Option<bool> {
    let (t0, t1) = b.domain();
    let mut params: Vec<f64> = Vec::with_capacity(7);
    for k in 1..8 {
        let t = t0 + (t1 - t0) * k as f64 / 8.0;
        let target = b.point_at(t);
        let near = params
            .last()
            .and_then(|&from| project_to_curve_locally(a, target, from).ok())
            .filter(|cp| cp.distance <= tol);
        let cp = match near {
            Some(cp) => cp,
            None => closest_point_on_curve(a, target).ok()?,
        };
        if cp.distance > tol {
            return None;
        }
        params.push(cp.t);
    }
    // Same way when the foot points advance along `a` as `b` advances.
    Some(params.last() > params.first())
}

/// The bounding box of a curve's control points (which contains the curve).
fn bounds(c: &Curve3) -> (DVec3, DVec3) {
    c.control_points().iter().fold(
        (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)),
        |(lo, hi), &p| (lo.min(p), hi.max(p)),
    )
}

fn inside_box(p: DVec3, lo: DVec3, hi: DVec3, tol: f64) -> bool {
    p.cmpge(lo - tol).all() && p.cmple(hi + tol).all()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::interpolate::{interpolate, Interpolation};

    /// What `coincide` answered before it marched: the global search for every sample.
    fn coincide_globally(a: &Curve3, b: &Curve3, tol: f64) -> Option<bool> {
        let (t0, t1) = b.domain();
        let mut params = Vec::new();
        for k in 1..8 {
            let t = t0 + (t1 - t0) * k as f64 / 8.0;
            let cp = closest_point_on_curve(a, b.point_at(t)).ok()?;
            if cp.distance > tol {
                return None;
            }
            params.push(cp.t);
        }
        Some(params.last() > params.first())
    }

    /// A long wavy outline of many spans, `bulge` mm off in its middle third.
    fn outline(count: usize, bulge: f64) -> Curve3 {
        let points: Vec<DVec3> = (0..count)
            .map(|i| {
                let x = 1200.0 * i as f64 / (count - 1) as f64;
                let middle = if (400.0..=800.0).contains(&x) {
                    bulge * ((x - 400.0) / 400.0 * std::f64::consts::PI).sin()
                } else {
                    0.0
                };
                DVec3::new(x, 40.0 * (x / 90.0).sin() + middle, 15.0 * (x / 70.0).cos())
            })
            .collect();
        interpolate(&points, &Interpolation::default()).expect("distinct points interpolate")
    }

    #[test]
    fn marching_answers_what_the_global_search_answers() {
        let tol = 0.01;
        let a = outline(241, 0.0);
        // The same outline through other points (another parametrization), one bulging
        // by ten times the tolerance, one by half of it.
        let again = outline(301, 0.0);
        let off = outline(301, 0.1);
        let within = outline(301, 0.004);
        let cases = [
            (&a, a.clone(), Some(true)),
            (&a, a.reversed(), Some(false)),
            (&a, again.clone(), Some(true)),
            (&a, again.reversed(), Some(false)),
            (&a, off.clone(), None),
            (&a, off.reversed(), None),
            (&a, within.reversed(), Some(false)),
        ];
        for (k, (a, b, expected)) in cases.iter().enumerate() {
            assert_eq!(coincide(a, b, tol), *expected, "case {k}");
            assert_eq!(
                coincide_globally(a, b, tol),
                *expected,
                "case {k}, the reference"
            );
        }
    }
}
