//! A face imprinted onto a shell from above: a draw bead's skin set into the binder
//! it stands on, so that one conforming mesh carries both (issue 18).
//!
//! A bead's skin stands on the binder along its feet and runs out into it at its ends,
//! so its boundary (the footprint) lies on the binder's faces. Seen from above (press
//! Z, the direction the binder closes in), the footprint is a closed loop over those
//! faces. Imprinting it:
//!
//! 1. finds where the footprint crosses the shell's edges in the top view (a bead that
//!    runs from a binder side round a corner patch crosses their seams), and splits
//!    those edges and the footprint there, at one shared vertex each;
//! 2. gives every face the footprint touches its new boundary: its own edges outside
//!    the footprint and the footprint's pieces over it, run the other way; a footprint
//!    inside one face leaves a hole in it, and a face the footprint cuts in two becomes
//!    two faces on the same surface;
//! 3. adds the imprinted face, bounded by the footprint's pieces, oriented like the
//!    faces under it.
//!
//! The shell stays oriented (every shared edge used once each way), and the faces
//! under the footprint and the imprinted face share the footprint's edges, so a mesh
//! of the shell ([`super::mesh::quad::shell`]) puts the same nodes along the bead's
//! feet on both sides.

use glam::{DVec2, DVec3};

use super::curve::Curve3;
use super::error::GeomError;
use super::sew::{Edge, Face, SewnFace, Shell};
use super::trimmed::{polygon_area, winding};

/// The most samples a curve's top-view trace takes.
const MAX_SAMPLES: usize = 4000;
/// The spacing of a curve's top-view trace (mm): crossings closer than this along one
/// curve are not told apart.
const SAMPLE_STEP: f64 = 1.0;

/// Why a face could not be imprinted.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ImprintError {
    /// The footprint leaves the shell: it crosses the shell's free boundary, or part
    /// of it lies over no face.
    #[error("its edge runs off the faces under it near ({:.1}, {:.1}, {:.1})", at.x, at.y, at.z)]
    OffShell {
        /// Where (mm).
        at: DVec3,
    },
    /// The footprint passes through (within the tolerance of) a corner of the faces
    /// under it, or one of its own corners lies on their edge: the split would leave
    /// a sliver.
    #[error("its edge passes through a corner of the faces under it near ({:.1}, {:.1}, {:.1})", at.x, at.y, at.z)]
    ThroughCorner {
        /// Where (mm).
        at: DVec3,
    },
    /// The faces under the footprint do not all face the same way seen from above (a
    /// wall, or a face folded over in the top view).
    #[error("the faces under it near ({:.1}, {:.1}, {:.1}) do not all face up (or all down) seen from above", at.x, at.y, at.z)]
    NotFromAbove {
        /// Where (mm).
        at: DVec3,
    },
    /// The footprint covers a whole face.
    #[error("it covers the whole face `{name}`")]
    Covers {
        /// The face's name.
        name: String,
    },
    /// The face's boundary encloses no area seen from above.
    #[error("its boundary encloses no area seen from above")]
    Degenerate,
    /// The new boundaries do not close into loops (the footprint touches an edge
    /// without crossing it, or runs along one).
    #[error("its edge runs along the edges under it near ({:.1}, {:.1}, {:.1}) instead of crossing them", at.x, at.y, at.z)]
    Tangled {
        /// Where (mm).
        at: DVec3,
    },
    /// A curve could not be cut.
    #[error(transparent)]
    Kernel(#[from] GeomError),
}

/// What [`imprint`] changed in the shell's faces.
#[derive(Debug, Clone, PartialEq)]
pub struct Imprinted {
    /// The imprinted face's index in the shell (the last face).
    pub face: usize,
    /// Faces added because the footprint cut a face in two or more: `(new face, the
    /// face it was cut from)`, both indices in the shell.
    pub split: Vec<(usize, usize)>,
}

/// A curve seen from above: samples of its parameter and top-view point, and their
/// bounding box.
struct Trace {
    params: Vec<f64>,
    xy: Vec<DVec2>,
    lo: DVec2,
    hi: DVec2,
}

impl Trace {
    fn of(curve: &Curve3) -> Trace {
        let (t0, t1) = curve.domain();
        let n = ((curve.length() / SAMPLE_STEP).ceil() as usize).clamp(16, MAX_SAMPLES);
        let params: Vec<f64> = (0..=n)
            .map(|k| t0 + (t1 - t0) * k as f64 / n as f64)
            .collect();
        let xy: Vec<DVec2> = params
            .iter()
            .map(|&t| curve.point_at(t).truncate())
            .collect();
        let lo = xy
            .iter()
            .fold(DVec2::splat(f64::INFINITY), |m, p| m.min(*p));
        let hi = xy
            .iter()
            .fold(DVec2::splat(f64::NEG_INFINITY), |m, p| m.max(*p));
        Trace { params, xy, lo, hi }
    }

    fn overlaps(&self, other: &Trace, pad: f64) -> bool {
        self.lo.x <= other.hi.x + pad
            && other.lo.x <= self.hi.x + pad
            && self.lo.y <= other.hi.y + pad
            && other.lo.y <= self.hi.y + pad
    }
}

/// One place where the footprint crosses a shell edge in the top view.
#[derive(Debug, Clone, Copy)]
struct Crossing {
    /// The footprint curve and its parameter there.
    foot: usize,
    s: f64,
    /// The shell edge and its parameter there.
    edge: usize,
    t: f64,
    /// The point on the shell edge (the shared vertex).
    at: DVec3,
}

/// Imprints `face` onto `shell` seen from above (press Z): the faces its boundary
/// lies over lose the part it covers, and it joins the shell sharing its boundary
/// with them. `tol` (mm) is how near a crossing may come to a corner.
///
/// Errors: the boundary runs off the shell or through a corner, along an edge, over
/// faces that do not all face one way from above, or over a whole face; see
/// [`ImprintError`]. On an error the shell is left as it was.
pub fn imprint(shell: &mut Shell, face: Face, tol: f64) -> Result<Imprinted, ImprintError> {
    let foot = face.boundary(tol);
    let foot_traces: Vec<Trace> = foot.iter().map(Trace::of).collect();
    let foot_polygon: Vec<DVec2> = foot_traces
        .iter()
        .flat_map(|t| t.xy[..t.xy.len() - 1].iter().copied())
        .collect();
    let foot_area = polygon_area(foot_polygon.iter().copied());
    if foot.len() < 2 || foot_area.abs() <= 1e-9 {
        return Err(ImprintError::Degenerate);
    }
    let edge_traces: Vec<Trace> = shell.edges.iter().map(|e| Trace::of(&e.curve)).collect();
    let face_polygons: Vec<Vec<Vec<DVec2>>> = shell
        .faces
        .iter()
        .map(|f| face_polygon(f, &edge_traces))
        .collect();
    let uses = shell.edge_uses();

    // 1. Crossings, and the new vertices at them.
    let mut crossings = Vec::new();
    for (i, ft) in foot_traces.iter().enumerate() {
        for (e, et) in edge_traces.iter().enumerate() {
            if uses[e] > 0 && ft.overlaps(et, tol) {
                crossings.extend(cross(i, &foot[i], ft, e, &shell.edges[e].curve, et));
            }
        }
    }
    for c in &crossings {
        if uses[c.edge] == 1 {
            return Err(ImprintError::OffShell { at: c.at });
        }
        let edge = &shell.edges[c.edge];
        let near_corner = |p: DVec3| p.truncate().distance(c.at.truncate()) <= tol;
        if near_corner(shell.vertices[edge.start])
            || near_corner(shell.vertices[edge.end])
            || near_corner(foot[c.foot].start_point())
            || near_corner(foot[c.foot].end_point())
        {
            return Err(ImprintError::ThroughCorner { at: c.at });
        }
    }

    // 2. The footprint cut at the crossings into pieces, each over one face.
    let mut vertices = shell.vertices.clone();
    let mut edges = shell.edges.clone();
    let corner_ids: Vec<usize> = foot
        .iter()
        .map(|c| {
            vertices.push(c.start_point());
            vertices.len() - 1
        })
        .collect();
    let crossing_ids: Vec<usize> = crossings
        .iter()
        .map(|c| {
            vertices.push(c.at);
            vertices.len() - 1
        })
        .collect();
    // (footprint edge id, the face under it)
    let mut pieces: Vec<(usize, usize)> = Vec::new();
    for (i, curve) in foot.iter().enumerate() {
        let cuts = crossings
            .iter()
            .zip(&crossing_ids)
            .filter(|(c, _)| c.foot == i)
            .map(|(c, &v)| (c.s, v));
        let ends = (corner_ids[i], corner_ids[(i + 1) % foot.len()]);
        for piece in cut(curve, ends, cuts)? {
            let (a, b) = piece.curve.domain();
            let mid = piece.curve.point_at(0.5 * (a + b));
            let under = face_at(&face_polygons, mid.truncate())
                .ok_or(ImprintError::OffShell { at: mid })?;
            edges.push(piece);
            pieces.push((edges.len() - 1, under));
        }
    }

    // The faces under the footprint must all face the same way from above, and the
    // imprinted face is turned to match them.
    let mut touched: Vec<usize> = pieces.iter().map(|p| p.1).collect();
    for c in &crossings {
        touched.extend(
            shell
                .faces
                .iter()
                .enumerate()
                .filter(|(_, f)| f.loop_edges().any(|&(e, _)| e == c.edge))
                .map(|(k, _)| k),
        );
    }
    touched.sort_unstable();
    touched.dedup();
    // A face the footprint neither crosses nor lies over is wholly outside it, or
    // wholly inside it: covered.
    for (f, polygon) in face_polygons.iter().enumerate() {
        if touched.binary_search(&f).is_err()
            && winding(foot_polygon.iter().copied(), polygon[0][0]) != 0
        {
            return Err(ImprintError::Covers {
                name: shell.faces[f].face.name.clone(),
            });
        }
    }
    let up = polygon_area(face_polygons[touched[0]][0].iter().copied()) > 0.0;
    for &f in &touched {
        if (polygon_area(face_polygons[f][0].iter().copied()) > 0.0) != up {
            return Err(ImprintError::NotFromAbove {
                at: foot[0].start_point(),
            });
        }
    }
    // The imprinted face's loop runs the way the faces' outer loops run from above.
    let foot_forward = (foot_area > 0.0) == up;

    // 3. The crossed edges cut at their crossings.
    let mut replaced: Vec<Option<Vec<usize>>> = vec![None; shell.edges.len()];
    for e in 0..shell.edges.len() {
        if !crossings.iter().any(|c| c.edge == e) {
            continue;
        }
        let cuts = crossings
            .iter()
            .zip(&crossing_ids)
            .filter(|(c, _)| c.edge == e)
            .map(|(c, &v)| (c.t, v));
        let original = &shell.edges[e];
        let cut_pieces = cut(&original.curve, (original.start, original.end), cuts)?;
        let mut ids = Vec::with_capacity(cut_pieces.len());
        for (k, piece) in cut_pieces.into_iter().enumerate() {
            if k == 0 {
                edges[e] = piece;
                ids.push(e);
            } else {
                edges.push(piece);
                ids.push(edges.len() - 1);
            }
        }
        replaced[e] = Some(ids);
    }
    let replace = |l: &[(usize, bool)]| -> Vec<(usize, bool)> {
        let mut out = Vec::with_capacity(l.len());
        for &(e, forward) in l {
            match &replaced[e] {
                None => out.push((e, forward)),
                Some(ids) if forward => out.extend(ids.iter().map(|&p| (p, true))),
                Some(ids) => out.extend(ids.iter().rev().map(|&p| (p, false))),
            }
        }
        out
    };

    // 4. Each touched face bounded anew: its edges outside the footprint, and the
    // footprint's pieces over it run against the imprinted face's loop.
    let mut faces = shell.faces.clone();
    let mut split = Vec::new();
    for &f in &touched {
        let mut directed: Vec<(usize, bool)> = Vec::new();
        for l in std::iter::once(&faces[f].bound).chain(&faces[f].holes) {
            for (e, forward) in replace(l) {
                let c = &edges[e].curve;
                let (t0, t1) = c.domain();
                let mid = c.point_at(0.5 * (t0 + t1)).truncate();
                if winding(foot_polygon.iter().copied(), mid) == 0 {
                    directed.push((e, forward));
                }
            }
        }
        directed.extend(
            pieces
                .iter()
                .filter(|p| p.1 == f)
                .map(|p| (p.0, !foot_forward)),
        );
        let loops = chain(&directed, &edges, &vertices)?;
        let (mut outers, holes): (Vec<_>, Vec<_>) = loops
            .into_iter()
            .map(|l| {
                let polygon = loop_polygon(&l, &edges);
                (l, polygon)
            })
            .partition(|(_, polygon)| (polygon_area(polygon.iter().copied()) > 0.0) == up);
        if outers.is_empty() {
            return Err(ImprintError::Covers {
                name: faces[f].face.name.clone(),
            });
        }
        // Largest first, so the face keeps its index for the main part of it.
        outers.sort_by(|a, b| {
            polygon_area(b.1.iter().copied())
                .abs()
                .total_cmp(&polygon_area(a.1.iter().copied()).abs())
        });
        let mut parts: Vec<SewnFace> = outers
            .iter()
            .map(|(l, _)| SewnFace {
                face: faces[f].face.clone(),
                bound: l.clone(),
                holes: Vec::new(),
                reversed: faces[f].reversed,
            })
            .collect();
        for (hole, polygon) in holes {
            let inside = outers
                .iter()
                .position(|(_, outer)| winding(outer.iter().copied(), polygon[0]) != 0)
                // A hole lies inside one of the face's outer loops; should its first
                // point fall exactly on an outer loop's trace, the largest part takes it.
                .unwrap_or(0);
            parts[inside].holes.push(hole);
        }
        let mut parts = parts.into_iter();
        if let Some(first) = parts.next() {
            faces[f] = first;
        }
        for part in parts {
            faces.push(part);
            split.push((faces.len() - 1, f));
        }
    }
    // 5. The imprinted face.
    let mut bound: Vec<(usize, bool)> = pieces.iter().map(|p| (p.0, true)).collect();
    if !foot_forward {
        bound.reverse();
        for b in &mut bound {
            b.1 = false;
        }
    }
    faces.push(SewnFace {
        face,
        bound,
        holes: Vec::new(),
        reversed: !foot_forward,
    });
    shell.vertices = vertices;
    shell.edges = edges;
    shell.faces = faces;
    Ok(Imprinted {
        face: shell.faces.len() - 1,
        split,
    })
}

/// `curve` (from vertex `ends.0` to `ends.1`) cut at each `(parameter, vertex)` of
/// `cuts`, as edges in order along it.
fn cut(
    curve: &Curve3,
    ends: (usize, usize),
    cuts: impl Iterator<Item = (f64, usize)>,
) -> Result<Vec<Edge>, ImprintError> {
    let (t0, t1) = curve.domain();
    let mut at = vec![(t0, ends.0)];
    let mut inner: Vec<(f64, usize)> = cuts.collect();
    inner.sort_by(|a, b| a.0.total_cmp(&b.0));
    at.extend(inner);
    at.push((t1, ends.1));
    at.windows(2)
        .map(|w| {
            Ok(Edge {
                curve: curve.between(w[0].0, w[1].0)?,
                start: w[0].1,
                end: w[1].1,
            })
        })
        .collect()
}

/// A face's loops seen from above, each as a closed polygon (outer first).
fn face_polygon(face: &SewnFace, traces: &[Trace]) -> Vec<Vec<DVec2>> {
    std::iter::once(&face.bound)
        .chain(&face.holes)
        .map(|l| {
            let mut polygon = Vec::new();
            for &(e, forward) in l {
                let xy = &traces[e].xy;
                if forward {
                    polygon.extend(&xy[..xy.len() - 1]);
                } else {
                    polygon.extend(xy[1..].iter().rev());
                }
            }
            polygon
        })
        .collect()
}

/// The face whose region (seen from above) holds `q`: inside its outer loop and
/// outside its holes; the first such face.
fn face_at(polygons: &[Vec<Vec<DVec2>>], q: DVec2) -> Option<usize> {
    polygons.iter().position(|loops| {
        winding(loops[0].iter().copied(), q) != 0
            && loops[1..]
                .iter()
                .all(|h| winding(h.iter().copied(), q) == 0)
    })
}

/// A loop of directed edges seen from above, as a polygon.
fn loop_polygon(l: &[(usize, bool)], edges: &[Edge]) -> Vec<DVec2> {
    let mut polygon = Vec::new();
    for &(e, forward) in l {
        let t = Trace::of(&edges[e].curve);
        if forward {
            polygon.extend(&t.xy[..t.xy.len() - 1]);
        } else {
            polygon.extend(t.xy[1..].iter().rev());
        }
    }
    polygon
}

/// The directed edges joined end to start into closed loops; every vertex must have
/// exactly one edge leaving it.
fn chain(
    directed: &[(usize, bool)],
    edges: &[Edge],
    vertices: &[DVec3],
) -> Result<Vec<Vec<(usize, bool)>>, ImprintError> {
    let ends = |&(e, forward): &(usize, bool)| {
        let edge = &edges[e];
        if forward {
            (edge.start, edge.end)
        } else {
            (edge.end, edge.start)
        }
    };
    let mut leaving: std::collections::BTreeMap<usize, usize> = Default::default();
    for (k, d) in directed.iter().enumerate() {
        let (start, _) = ends(d);
        if leaving.insert(start, k).is_some() {
            return Err(ImprintError::Tangled {
                at: vertices[start],
            });
        }
    }
    let mut used = vec![false; directed.len()];
    let mut loops = Vec::new();
    for first in 0..directed.len() {
        if used[first] {
            continue;
        }
        let mut l = Vec::new();
        let mut k = first;
        while !used[k] {
            used[k] = true;
            l.push(directed[k]);
            let (_, end) = ends(&directed[k]);
            k = *leaving
                .get(&end)
                .ok_or(ImprintError::Tangled { at: vertices[end] })?;
        }
        if k != first {
            return Err(ImprintError::Tangled {
                at: vertices[ends(&directed[k]).0],
            });
        }
        loops.push(l);
    }
    Ok(loops)
}

/// Where the footprint curve `i` crosses the shell edge `e` seen from above, each
/// crossing refined by Newton on the two curves.
fn cross(
    i: usize,
    foot: &Curve3,
    ft: &Trace,
    e: usize,
    edge: &Curve3,
    et: &Trace,
) -> Vec<Crossing> {
    let mut out: Vec<Crossing> = Vec::new();
    let (nf, ne) = (ft.xy.len() - 1, et.xy.len() - 1);
    for a in 0..nf {
        let (p, q) = (ft.xy[a], ft.xy[a + 1]);
        let (lo, hi) = (p.min(q), p.max(q));
        if lo.x > et.hi.x || hi.x < et.lo.x || lo.y > et.hi.y || hi.y < et.lo.y {
            continue;
        }
        for b in 0..ne {
            let (r, s) = (et.xy[b], et.xy[b + 1]);
            if r.min(s).x > hi.x || r.max(s).x < lo.x || r.min(s).y > hi.y || r.max(s).y < lo.y {
                continue;
            }
            // Half-open on both, so a crossing at a shared sample is found once.
            let last = (a + 1 == nf, b + 1 == ne);
            let Some((u, v)) = segment_params(p, q, r, s, last) else {
                continue;
            };
            let s0 = ft.params[a] + u * (ft.params[a + 1] - ft.params[a]);
            let t0 = et.params[b] + v * (et.params[b + 1] - et.params[b]);
            let (s, t) = refine(foot, edge, s0, t0);
            out.push(Crossing {
                foot: i,
                s,
                edge: e,
                t,
                at: edge.point_at(t),
            });
        }
    }
    out
}

/// The parameters `(u, v)` at which the segments `p q` and `r s` cross (`u` along
/// `p q`), each in `[0, 1)`, or `[0, 1]` when `last` says the segment is its curve's
/// last; `None` when they do not cross or are parallel.
fn segment_params(
    p: DVec2,
    q: DVec2,
    r: DVec2,
    s: DVec2,
    last: (bool, bool),
) -> Option<(f64, f64)> {
    let (d1, d2) = (q - p, s - r);
    let denom = d1.perp_dot(d2);
    if denom.abs() <= 1e-15 * d1.length() * d2.length() {
        return None;
    }
    let u = (r - p).perp_dot(d2) / denom;
    let v = (r - p).perp_dot(d1) / denom;
    let within = |x: f64, closed: bool| x >= 0.0 && (x < 1.0 || (closed && x <= 1.0));
    (within(u, last.0) && within(v, last.1)).then_some((u, v))
}

/// Newton on `foot(s) - edge(t) = 0` in the top view, from `(s, t)`; the start is
/// kept when Newton leaves the domains or does not settle.
fn refine(foot: &Curve3, edge: &Curve3, s: f64, t: f64) -> (f64, f64) {
    let ((a0, a1), (b0, b1)) = (foot.domain(), edge.domain());
    let (mut s1, mut t1) = (s, t);
    for _ in 0..20 {
        let [f, df] = foot.derivatives::<2>(s1);
        let [g, dg] = edge.derivatives::<2>(t1);
        let r = (f - g).truncate();
        if r.length() <= 1e-10 {
            return (s1, t1);
        }
        // r + df ds - dg dt = 0
        let (a, b) = (df.truncate(), -dg.truncate());
        let det = a.perp_dot(b);
        if det.abs() <= 1e-300 {
            break;
        }
        let ds = -r.perp_dot(b) / det;
        let dt = -a.perp_dot(r) / det;
        s1 += ds;
        t1 += dt;
        if !(a0..=a1).contains(&s1) || !(b0..=b1).contains(&t1) {
            break;
        }
    }
    let [f] = foot.derivatives::<1>(s1);
    let [g] = edge.derivatives::<1>(t1);
    if (a0..=a1).contains(&s1) && (b0..=b1).contains(&t1) && (f - g).truncate().length() <= 1e-6 {
        (s1, t1)
    } else {
        (s, t)
    }
}
