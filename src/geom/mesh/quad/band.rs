//! A die radius meshed as a forming engineer meshes it: a four-sided patch whose
//! sections curve tighter than the element size can follow (a step draw's patch, with
//! its die radius and wall across it) meshed as one band of mapped quads, rows running
//! along the patch at fixed values of the parameter across it, spaced by the sections'
//! curvature so no chord across a radius sags more than the chordal tolerance, and
//! columns across it spaced by the element size (closer where the rows curve in plan).
//!
//! The unstructured splitting of [`super::split`] keeps elements about as long as
//! they are wide, so where a radius asks for 4 mm across and the seams bring 7 to 10 mm
//! along, it cannot shrink within one element and the chords across the radius sag
//! (BENCHMARKS.md, "Chord sag off the surfaces"). A band's quads are long along the
//! radius and short across it, which is what the radius needs.
//!
//! The band's seam nodes are placed by the band itself ([`Band::side_nodes`]): the
//! rows' ends on its two section sides (shared, with the same rows, by the band next to
//! it: a step draw's patches are one group with one set of rows) and the columns' ends
//! on its two long sides (shared with unstructured faces: the product, the binder).
//! Every band's loop is even by construction; an odd neighbour is mended by one more
//! column ([`Band::add_column`]), which passes the odd count on across the band.

use glam::DVec3;
use rayon::prelude::*;

use super::sizing::{chord_for_sag, chord_measures, circumradius};
use crate::geom::inversion::closest_point_on_curve;
use crate::geom::mesh::{Face, Mesh};
use crate::geom::sew::{Shape, Shell};
use crate::geom::surface::{Direction, NurbsSurface};

/// Samples along a band's sections for its rows, and along its length for its columns.
const SAMPLES: usize = 512;

/// Sections sampled across a band's length when its rows are chosen.
const SECTIONS: usize = 9;

/// The share of the chordal tolerance a chord across a band (between two rows) may
/// sag: an element's centre sags by about its chord across and its chord along
/// together, so the chords along a row keep to what is left beside it.
const ROW_SHARE: f64 = 0.8;

/// The least scaled Jacobian (against the surface normal) a band's mapped quads must
/// keep; a band poorer than this is meshed unstructured instead, on the same seam nodes.
pub const LEAST_BAND_QUALITY: f64 = 0.2;

/// A column of a band: its along parameter on the first long side and on the
/// second, and whether it ends at a seam vertex on each.
#[derive(Debug, Clone, Copy)]
struct Column {
    b: (f64, f64),
    vertex: [bool; 2],
}

/// One side of a band: which parameter is fixed on it and where, and its edges.
#[derive(Debug, Clone)]
struct Side {
    /// The outer loop's entries (indices into the face's `bound`) along this side, in
    /// loop order.
    entries: Vec<usize>,
    /// Whether the loop runs along this side with its parameter rising.
    rising: bool,
}

/// A face meshed as a band of mapped quads.
#[derive(Debug, Clone)]
pub struct Band {
    /// The face's index in the shell.
    pub face: usize,
    /// The parameter running across the band (along its sections): the rows lie at
    /// fixed values of it.
    across: Direction,
    /// The across parameter's domain, and the along parameter's.
    a: (f64, f64),
    b: (f64, f64),
    /// The sides: `a` at its start, `a` at its end (the long sides, carrying the
    /// columns' ends), `b` at its start, `b` at its end (the section sides, carrying
    /// the rows' ends).
    sides: [Side; 4],
    /// The rows as fractions of the across domain, 0 first and 1 last.
    rows: Vec<f64>,
    /// The along parameter of the seam vertices inside each long side, rising: a
    /// column must end at each.
    vertices: [Vec<f64>; 2],
    /// How many columns' widths the band is divided into.
    count: usize,
    /// The length measure along the band: at each along sample, elements' widths so
    /// far (the largest over the rows).
    measure: Vec<f64>,
}

impl Band {
    /// The point of the band's surface at across fraction `s` and along parameter `b`.
    fn point(&self, surface: &NurbsSurface, s: f64, b: f64) -> DVec3 {
        let a = self.a.0 + s * (self.a.1 - self.a.0);
        match self.across {
            Direction::U => surface.point_at(a, b),
            Direction::V => surface.point_at(b, a),
        }
    }

    /// The along parameter at along sample position `x` (0 to `SAMPLES`).
    fn along_at(&self, x: f64) -> f64 {
        self.b.0 + (self.b.1 - self.b.0) * x / SAMPLES as f64
    }

    /// The along sample position where the measure reaches `m`.
    fn position_of(&self, m: f64) -> f64 {
        let k = self.measure.partition_point(|&x| x < m).clamp(1, SAMPLES);
        let (m0, m1) = (self.measure[k - 1], self.measure[k]);
        let s = if m1 > m0 { (m - m0) / (m1 - m0) } else { 0.0 };
        (k - 1) as f64 + s.clamp(0.0, 1.0)
    }

    /// The measure at along parameter `b`.
    fn measure_at(&self, b: f64) -> f64 {
        let x =
            ((b - self.b.0) / (self.b.1 - self.b.0) * SAMPLES as f64).clamp(0.0, SAMPLES as f64);
        let k = (x.floor() as usize).min(SAMPLES - 1);
        self.measure[k] + (x - k as f64) * (self.measure[k + 1] - self.measure[k])
    }

    /// The measure between the seam vertices of long side `k` (and its ends).
    fn intervals(&self, k: usize) -> (Vec<f64>, Vec<f64>) {
        let ends: Vec<f64> = std::iter::once(self.b.0)
            .chain(self.vertices[k].iter().copied())
            .chain(std::iter::once(self.b.1))
            .collect();
        let widths = ends
            .windows(2)
            .map(|w| self.measure_at(w[1]) - self.measure_at(w[0]))
            .collect();
        (ends, widths)
    }

    /// The fewest columns' widths each long side asks for: a whole number between
    /// each two of its seam vertices, one at least.
    fn least_count(&self) -> usize {
        (0..2)
            .map(|k| {
                let (_, widths) = self.intervals(k);
                widths.iter().fold(0usize, |n, &w| {
                    n.saturating_add((w.round() as usize).max(1))
                })
            })
            .max()
            .unwrap_or(1)
    }

    /// The along parameter of each column's end on long side `k`, from the band's
    /// start to its end, and whether it is a seam vertex: the band's `count` widths
    /// shared among the side's intervals by their measure, each divided evenly.
    fn side_columns(&self, k: usize) -> Vec<(f64, bool)> {
        let (ends, widths) = self.intervals(k);
        let mut counts: Vec<usize> = widths
            .iter()
            .map(|&w| (w.round() as usize).max(1))
            .collect();
        while counts.iter().sum::<usize>() < self.count {
            let widest = (0..counts.len())
                .max_by(|&i, &j| {
                    (widths[i] / counts[i] as f64)
                        .total_cmp(&(widths[j] / counts[j] as f64))
                        .then(j.cmp(&i))
                })
                .unwrap_or(0);
            counts[widest] += 1;
        }
        let mut out = vec![(self.b.0, false)];
        for (i, &c) in counts.iter().enumerate() {
            let (m0, m1) = (self.measure_at(ends[i]), self.measure_at(ends[i + 1]));
            for j in 1..c {
                let f = j as f64 / c as f64;
                out.push((self.along_at(self.position_of(m0 + f * (m1 - m0))), false));
            }
            out.push((ends[i + 1], i + 1 < counts.len()));
        }
        out
    }

    /// The columns: the along parameter of each on the first long side and on the
    /// second (node `j` of one side joined to node `j` of the other), from the band's
    /// start to its end.
    fn columns(&self) -> Vec<Column> {
        let (first, second) = (self.side_columns(0), self.side_columns(1));
        first
            .iter()
            .zip(&second)
            .map(|(x, y)| Column {
                b: (x.0, y.0),
                vertex: [x.1, y.1],
            })
            .collect()
    }

    /// One more column: every loop through the band's long sides changes parity, the
    /// band's own stays even.
    pub fn add_column(&mut self) {
        self.count += 1;
    }

    /// Whether shell edge `e` lies on one of the band's long sides (where its columns
    /// end).
    pub fn on_long_side(&self, shell: &Shell, e: usize) -> bool {
        let bound = &shell.faces[self.face].bound;
        self.sides[..2]
            .iter()
            .any(|side| side.entries.iter().any(|&k| bound[k].0 == e))
    }

    /// The shell edges of the band's outer loop with the inner nodes the band puts on
    /// each, in the edge's own direction: `(edge, nodes)`.
    pub fn side_nodes(&self, shell: &Shell) -> Vec<(usize, Vec<DVec3>)> {
        let face = &shell.faces[self.face];
        let surface = face.face.surface();
        let columns = self.columns();
        let mut out = Vec::new();
        for (k, side) in self.sides.iter().enumerate() {
            // The side's nodes between its ends, rising, each with whether it is a
            // seam vertex (which ends one edge of the side and starts the next).
            let nodes: Vec<(DVec3, bool)> = match k {
                0 | 1 => columns[1..columns.len() - 1]
                    .iter()
                    .map(|c| {
                        let b = if k == 0 { c.b.0 } else { c.b.1 };
                        (self.point(surface, k as f64, b), c.vertex[k])
                    })
                    .collect(),
                _ => {
                    let b = if k == 2 { self.b.0 } else { self.b.1 };
                    self.rows[1..self.rows.len() - 1]
                        .iter()
                        .map(|&s| (self.point(surface, s, b), false))
                        .collect()
                }
            };
            let entries: Vec<usize> = if side.rising {
                side.entries.clone()
            } else {
                side.entries.iter().rev().copied().collect()
            };
            let mut pieces = nodes.split(|n| n.1);
            for &entry in &entries {
                let (e, forward) = face.bound[entry];
                let mut inner: Vec<DVec3> =
                    pieces.next().unwrap_or(&[]).iter().map(|n| n.0).collect();
                if forward != side.rising {
                    inner.reverse();
                }
                out.push((e, inner));
            }
        }
        out
    }

    /// The along parameter of `p` on the long side at across fraction `s`.
    fn along_of(&self, surface: &NurbsSurface, s: f64, p: DVec3) -> f64 {
        let a = self.a.0 + s * (self.a.1 - self.a.0);
        let curve = surface.iso_curve(self.across, a);
        closest_point_on_curve(&curve, p).map_or(self.b.0, |c| c.t)
    }

    /// The band's elements on its loop's nodes: `boundary` is the outer loop's nodes in
    /// loop order (the face's local nodes `0..boundary.len()`); the mesh has those first,
    /// then the band's inner nodes, its quads turned along the surface's `S_u x S_v`.
    /// `None` where the loop does not carry the band's nodes or a quad would be poorer
    /// than [`LEAST_BAND_QUALITY`].
    pub fn mesh(&self, shell: &Shell, segments: &[usize], boundary: &[DVec3]) -> Option<Mesh> {
        let face = &shell.faces[self.face];
        let surface = face.face.surface();
        // Where each loop entry starts among the loop's nodes.
        let mut start = Vec::with_capacity(face.bound.len());
        let mut n = 0;
        for &(e, _) in &face.bound {
            start.push(n);
            n += segments[e];
        }
        if n != boundary.len() {
            return None;
        }
        // A side's local nodes, rising, both ends included.
        let side_ids = |side: &Side| -> Vec<u32> {
            let first = start[side.entries[0]];
            let count: usize = side
                .entries
                .iter()
                .map(|&k| segments[face.bound[k].0])
                .sum();
            let mut ids: Vec<u32> = (0..=count).map(|k| ((first + k) % n) as u32).collect();
            if !side.rising {
                ids.reverse();
            }
            ids
        };
        let columns = self.columns();
        let (nc, nr) = (columns.len(), self.rows.len());

        let first = side_ids(&self.sides[0]);
        let second = side_ids(&self.sides[1]);
        let left = side_ids(&self.sides[2]);
        let right = side_ids(&self.sides[3]);
        if first.len() != nc || second.len() != nc || left.len() != nr || right.len() != nr {
            return None;
        }
        let mut grid = vec![vec![0u32; nc]; nr];
        let mut params = vec![vec![(0.0, 0.0); nc]; nr];
        // The inner nodes' parameters, numbered after the boundary's in row order.
        let mut inner = Vec::new();
        for (i, &s) in self.rows.iter().enumerate() {
            for (j, column) in columns.iter().enumerate() {
                let (b0, b1) = column.b;
                let b = b0 + s * (b1 - b0);
                params[i][j] = (s, b);
                grid[i][j] = if i == 0 {
                    first[j]
                } else if i + 1 == nr {
                    second[j]
                } else if j == 0 {
                    left[i]
                } else if j + 1 == nc {
                    right[i]
                } else {
                    inner.push((s, b));
                    (boundary.len() + inner.len() - 1) as u32
                };
            }
        }
        // The surface evaluated side by side (a band is the last face a shell's pool
        // finishes), each point where it is numbered.
        let mut positions = boundary.to_vec();
        positions.par_extend(inner.par_iter().map(|&(s, b)| self.point(surface, s, b)));
        // A quad (i, j), (i, j + 1), (i + 1, j + 1), (i + 1, j) turns clockwise in
        // (across, along): along -(S_u x S_v) when the rows lie at fixed u. The rows
        // of quads are checked side by side and kept in order.
        let turn = matches!(self.across, Direction::U);
        let rows: Option<Vec<Vec<Face>>> = (0..nr - 1)
            .into_par_iter()
            .map(|i| self.quad_row(surface, i, &grid, &params, &positions, turn))
            .collect();
        let faces: Vec<Face> = rows?.concat();
        Mesh::new(positions, faces).ok()
    }

    /// The quads between rows `i` and `i + 1` of the band's node `grid` (with each
    /// node's across fraction and along parameter in `params`), turned over when
    /// `turn`; `None` where one is poorer than [`LEAST_BAND_QUALITY`] against the
    /// surface normal at its centre.
    fn quad_row(
        &self,
        surface: &NurbsSurface,
        i: usize,
        grid: &[Vec<u32>],
        params: &[Vec<(f64, f64)>],
        positions: &[DVec3],
        turn: bool,
    ) -> Option<Vec<Face>> {
        let nc = grid[i].len();
        let mut faces = Vec::with_capacity(nc - 1);
        for j in 0..nc - 1 {
            let mut ids = [
                grid[i][j],
                grid[i][j + 1],
                grid[i + 1][j + 1],
                grid[i + 1][j],
            ];
            if turn {
                ids.reverse();
            }
            let corners: Vec<DVec3> = ids.iter().map(|&v| positions[v as usize]).collect();
            let (s, b) = (
                0.5 * (params[i][j].0 + params[i + 1][j + 1].0),
                0.25 * (params[i][j].1
                    + params[i][j + 1].1
                    + params[i + 1][j].1
                    + params[i + 1][j + 1].1),
            );
            let a = self.a.0 + s * (self.a.1 - self.a.0);
            let (u, v) = match self.across {
                Direction::U => (a, b),
                Direction::V => (b, a),
            };
            let normal = surface.normal(u, v).ok()?;
            if quality_against(&corners, normal) < LEAST_BAND_QUALITY {
                return None;
            }
            faces.push(Face::quad(ids[0], ids[1], ids[2], ids[3]));
        }
        Some(faces)
    }
}

/// The least corner sine of a quad against a surface normal: its scaled Jacobian,
/// negative where it is turned against the surface.
fn quality_against(corners: &[DVec3], normal: DVec3) -> f64 {
    let k = corners.len();
    (0..k)
        .map(|i| {
            let a = corners[(i + 1) % k] - corners[i];
            let b = corners[(i + k - 1) % k] - corners[i];
            let l = a.length() * b.length();
            if l <= f64::MIN_POSITIVE {
                -1.0
            } else {
                a.cross(b).dot(normal) / l
            }
        })
        .fold(f64::INFINITY, f64::min)
}

/// A face that may be a band: its across direction, its domains and its sides; `None`
/// unless it is an untrimmed patch without holes whose loop turns at its four corners
/// and whose sections (in one parameter) curve tighter than `size` allows at
/// `tolerance`.
fn candidate(shell: &Shell, f: usize, size: f64, tolerance: f64) -> Option<Band> {
    let face = &shell.faces[f];
    let Shape::Patch(surface) = &face.face.shape else {
        return None;
    };
    if !face.holes.is_empty() || tolerance <= 0.0 {
        return None;
    }
    let (u, v) = (surface.domain_u(), surface.domain_v());
    // The tightest section in each direction: the least chord allowed.
    let least_chord = |across: Direction| -> f64 {
        let mut least = f64::INFINITY;
        for l in 0..SECTIONS {
            let t = l as f64 / (SECTIONS - 1) as f64;
            let points: Vec<DVec3> = (0..=SAMPLES / 2)
                .map(|k| {
                    let s = k as f64 / (SAMPLES / 2) as f64;
                    match across {
                        Direction::U => {
                            surface.point_at(u.0 + s * (u.1 - u.0), v.0 + t * (v.1 - v.0))
                        }
                        Direction::V => {
                            surface.point_at(u.0 + t * (u.1 - u.0), v.0 + s * (v.1 - v.0))
                        }
                    }
                })
                .collect();
            for w in points.windows(3) {
                least = least.min(chord_for_sag(
                    circumradius(w[0], w[1], w[2]),
                    ROW_SHARE * tolerance,
                ));
            }
        }
        least
    };
    let (in_u, in_v) = (least_chord(Direction::U), least_chord(Direction::V));
    let across = if in_u <= in_v {
        Direction::U
    } else {
        Direction::V
    };
    if in_u.min(in_v) >= size {
        return None;
    }
    let (a, b) = match across {
        Direction::U => (u, v),
        Direction::V => (v, u),
    };
    let at = |s: f64, t: f64| -> DVec3 {
        match across {
            Direction::U => surface.point_at(s, t),
            Direction::V => surface.point_at(t, s),
        }
    };
    // The loop's vertices, and which of them are the patch's corners.
    let vertex = |k: usize| -> usize {
        let (e, forward) = face.bound[k];
        if forward {
            shell.edges[e].start
        } else {
            shell.edges[e].end
        }
    };
    let corners = [(a.0, b.0), (a.1, b.0), (a.1, b.1), (a.0, b.1)];
    let reach = 1e-3 * surface.control_scale().max(1.0);
    let mut at_corner: Vec<(usize, usize)> = Vec::new(); // (loop entry, corner)
    for k in 0..face.bound.len() {
        let p = shell.vertices[vertex(k)];
        let near: Vec<usize> = (0..4)
            .filter(|&c| at(corners[c].0, corners[c].1).distance(p) < reach)
            .collect();
        match near.as_slice() {
            [] => {}
            [c] => at_corner.push((k, *c)),
            _ => return None,
        }
    }
    if at_corner.len() != 4 {
        return None;
    }
    let mut seen = [false; 4];
    for &(_, c) in &at_corner {
        if std::mem::replace(&mut seen[c], true) {
            return None;
        }
    }
    let n = face.bound.len();
    let mut sides: [Option<Side>; 4] = [None, None, None, None];
    for w in 0..4 {
        let (k0, c0) = at_corner[w];
        let (k1, c1) = at_corner[(w + 1) % 4];
        let entries: Vec<usize> = (0..n)
            .map(|d| (k0 + d) % n)
            .take_while(|&k| k != k1)
            .collect();
        if entries.is_empty() {
            return None;
        }
        let (p0, p1) = (corners[c0], corners[c1]);
        let (slot, rising) = if p0.0 == p1.0 {
            (if p0.0 == a.0 { 0 } else { 1 }, p0.1 < p1.1)
        } else if p0.1 == p1.1 {
            (if p0.1 == b.0 { 2 } else { 3 }, p0.0 < p1.0)
        } else {
            return None;
        };
        if sides[slot].is_some() {
            return None;
        }
        sides[slot] = Some(Side { entries, rising });
    }
    let [Some(s0), Some(s1), Some(s2), Some(s3)] = sides else {
        return None;
    };
    // The section sides carry the group's rows: one edge each.
    if s2.entries.len() != 1 || s3.entries.len() != 1 {
        return None;
    }
    Some(Band {
        face: f,
        across,
        a,
        b,
        sides: [s0, s1, s2, s3],
        rows: Vec::new(),
        vertices: [Vec::new(), Vec::new()],
        count: 1,
        measure: Vec::new(),
    })
}

/// The faces of `shell` to mesh as bands, with their rows and columns: face `f` at
/// element size `sizes[f]`, chords sagging at most `tolerance`. Bands whose section
/// sides meet share one set of rows; a face whose long side meets another band is
/// meshed unstructured, and so is a band that would have more than `max_elements`
/// quads (left to the unstructured mesher's own limit).
pub fn find_bands(shell: &Shell, sizes: &[f64], tolerance: f64, max_elements: usize) -> Vec<Band> {
    let size_of = |f: usize| sizes.get(f).copied().unwrap_or(f64::INFINITY);
    // Each face looked at on its own, side by side, kept in face order.
    let mut bands: Vec<Band> = (0..shell.faces.len())
        .into_par_iter()
        .filter_map(|f| candidate(shell, f, size_of(f), tolerance))
        .collect();
    // Which band side each edge is on.
    loop {
        let mut on: std::collections::HashMap<usize, Vec<(usize, usize)>> = Default::default();
        for (i, band) in bands.iter().enumerate() {
            let face = &shell.faces[band.face];
            for (k, side) in band.sides.iter().enumerate() {
                for &entry in &side.entries {
                    on.entry(face.bound[entry].0).or_default().push((i, k));
                }
            }
        }
        // A long side against another band, or a section side against a long one.
        let mut drop = vec![false; bands.len()];
        for users in on.values() {
            if users.len() > 1 && users.iter().any(|&(_, k)| k < 2) {
                for &(i, _) in users {
                    drop[i] = true;
                }
            }
        }
        if !drop.contains(&true) {
            // Groups joined at section sides.
            let mut group: Vec<usize> = (0..bands.len()).collect();
            fn root(group: &mut [usize], mut i: usize) -> usize {
                while group[i] != i {
                    group[i] = group[group[i]];
                    i = group[i];
                }
                i
            }
            let mut keys: Vec<&usize> = on.keys().collect();
            keys.sort();
            for e in keys {
                let users = &on[e];
                if users.len() == 2 {
                    let (x, y) = (root(&mut group, users[0].0), root(&mut group, users[1].0));
                    group[x.max(y)] = x.min(y);
                }
            }
            let roots: Vec<usize> = (0..bands.len()).map(|i| root(&mut group, i)).collect();
            set_rows(shell, &mut bands, &roots, &size_of, tolerance, max_elements);
            bands.retain(|band| !band.rows.is_empty());
            // The columns at the finest size of the band and the faces beside its long
            // sides (a finer product refines its seam, as on any other face).
            let mut beside = vec![f64::INFINITY; shell.edges.len()];
            for (f, face) in shell.faces.iter().enumerate() {
                for &(e, _) in face.loop_edges() {
                    beside[e] = beside[e].min(size_of(f));
                }
            }
            bands.par_iter_mut().for_each(|band| {
                let bound = &shell.faces[band.face].bound;
                let size = band.sides[..2]
                    .iter()
                    .flat_map(|side| side.entries.iter().map(|&k| beside[bound[k].0]))
                    .fold(size_of(band.face), f64::min);
                set_columns(shell, band, size, tolerance);
            });
            bands.retain(|band| (band.rows.len() - 1).saturating_mul(band.count) <= max_elements);
            return bands;
        }
        let mut k = 0;
        bands.retain(|_| {
            k += 1;
            !drop[k - 1]
        });
    }
}

/// Each group's rows: across fractions where the measure (elements' heights across
/// the band, the tightest over its sections) reaches each whole number.
fn set_rows(
    shell: &Shell,
    bands: &mut [Band],
    roots: &[usize],
    size_of: &dyn Fn(usize) -> f64,
    tolerance: f64,
    max_elements: usize,
) {
    for r in 0..bands.len() {
        if roots[r] != r {
            continue;
        }
        let members: Vec<usize> = (0..bands.len()).filter(|&i| roots[i] == r).collect();
        let mut measure = vec![0.0f64; SAMPLES];
        for &i in &members {
            let band = &bands[i];
            let surface = shell.faces[band.face].face.surface();
            for l in 0..SECTIONS {
                let t = band.b.0 + (band.b.1 - band.b.0) * l as f64 / (SECTIONS - 1) as f64;
                let points: Vec<DVec3> = (0..=SAMPLES)
                    .map(|k| band.point(surface, k as f64 / SAMPLES as f64, t))
                    .collect();
                for (m, x) in measure.iter_mut().zip(chord_measures(
                    &points,
                    size_of(band.face),
                    ROW_SHARE * tolerance,
                )) {
                    *m = m.max(x);
                }
            }
        }
        let total: f64 = measure.iter().sum();
        // Too many rows (a tolerance far below the radii) is no band.
        if total.is_nan() || total >= max_elements as f64 {
            continue;
        }
        let count = (total.ceil() as usize).max(1);
        let rows = divide(&measure, count);
        for &i in &members {
            bands[i].rows = rows.clone();
        }
    }
}

/// `count + 1` fractions (0 first, 1 last) dividing pieces of `measure` (each
/// `1 / measure.len()` long) into `count` of equal measure.
fn divide(measure: &[f64], count: usize) -> Vec<f64> {
    let total: f64 = measure.iter().sum();
    let n = measure.len() as f64;
    let mut out = vec![0.0];
    let (mut walked, mut seg) = (0.0, 0);
    for k in 1..count {
        let target = total * k as f64 / count as f64;
        while seg + 1 < measure.len() && walked + measure[seg] < target {
            walked += measure[seg];
            seg += 1;
        }
        let s = ((target - walked) / measure[seg].max(f64::MIN_POSITIVE)).clamp(0.0, 1.0);
        out.push((seg as f64 + s) / n);
    }
    out.push(1.0);
    out
}

/// A band's columns: the measure along it (elements' widths, the widest over its
/// rows), the seam vertices on its long sides (paired where they stand across from
/// each other), and how many columns between them.
fn set_columns(shell: &Shell, band: &mut Band, size: f64, tolerance: f64) {
    let face = &shell.faces[band.face];
    let surface = face.face.surface();
    // How far the chords across the band sag beside each row (between a row and the
    // next, at the chord's middle, the most over the band's sections): an element's
    // centre sags by its chord across and its chord along together, so the chords
    // along a row keep to what the tolerance leaves.
    let rows = &band.rows;
    let across_sag: Vec<f64> = (0..rows.len().saturating_sub(1))
        .map(|i| {
            (0..SECTIONS)
                .map(|l| {
                    let b = band.b.0 + (band.b.1 - band.b.0) * l as f64 / (SECTIONS - 1) as f64;
                    let (p, q) = (
                        band.point(surface, rows[i], b),
                        band.point(surface, rows[i + 1], b),
                    );
                    let middle = band.point(surface, 0.5 * (rows[i] + rows[i + 1]), b);
                    middle.distance(0.5 * (p + q))
                })
                .fold(0.0, f64::max)
        })
        .collect();
    let mut pieces = vec![0.0f64; SAMPLES];
    for (i, &s) in rows.iter().enumerate() {
        let beside = across_sag[i.saturating_sub(1)].max(across_sag.get(i).copied().unwrap_or(0.0));
        let along = (tolerance - beside).max((1.0 - ROW_SHARE) * tolerance);
        let points: Vec<DVec3> = (0..=SAMPLES)
            .map(|k| band.point(surface, s, band.along_at(k as f64)))
            .collect();
        for (m, x) in pieces.iter_mut().zip(chord_measures(&points, size, along)) {
            *m = m.max(x);
        }
    }
    band.measure = std::iter::once(0.0)
        .chain(pieces.iter().scan(0.0, |acc, &x| {
            *acc += x;
            Some(*acc)
        }))
        .collect();
    // The seam vertices inside each long side, by their along parameter.
    let mut inside: [Vec<f64>; 2] = [Vec::new(), Vec::new()];
    for (k, list) in inside.iter_mut().enumerate() {
        let side = &band.sides[k];
        for &entry in side.entries.iter().skip(1) {
            let (e, forward) = face.bound[entry];
            let v = if forward {
                shell.edges[e].start
            } else {
                shell.edges[e].end
            };
            list.push(band.along_of(surface, k as f64, shell.vertices[v]));
        }
        list.sort_by(f64::total_cmp);
    }
    band.vertices = inside;
    band.count = band.least_count();
    if !band.measure.last().is_some_and(|m| m.is_finite()) {
        band.count = usize::MAX;
    }
}
