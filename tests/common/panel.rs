//! A test panel with holes over an analytic surface `z = height(x, y)` (issue 17): a
//! 1000 x 600 mm panel, gently domed (radius of curvature over 3 m) with a ridge along
//! y = 420 (radius down to about 40 mm), meshed by a constrained Delaunay triangulation
//! of an equilateral lattice with the outer edge and the holes' outlines as
//! constraints, then lifted onto the surface. Its holes: circles, slots and rounded
//! rectangles up to 80 mm across, one near the outer edge, some on the ridge. Shared by
//! the hole-filling tests and the benchmark (`bench`), so both fill the same panel.

#![allow(dead_code)] // each user takes its own subset

use glam::{DVec2, DVec3};
use spade::{ConstrainedDelaunayTriangulation, Point2, Triangulation};

use dieface::geom::mesh::{Face, Mesh};

/// The panel's size (mm).
pub const WIDTH: f64 = 1000.0;
pub const DEPTH: f64 = 600.0;

/// The dome's height and the ridge's height, line and half-width (mm).
const DOME: f64 = 30.0;
const RIDGE: f64 = 15.0;
const RIDGE_AT: f64 = 420.0;
const RIDGE_WIDTH: f64 = 35.0;

/// The surface's height at `(x, y)`.
pub fn height(x: f64, y: f64) -> f64 {
    use std::f64::consts::PI;
    let ridge = (y - RIDGE_AT) / RIDGE_WIDTH;
    DOME * (PI * x / WIDTH).sin() * (PI * y / DEPTH).sin() + RIDGE * (-ridge * ridge).exp()
}

/// The height's gradient and second derivatives `(fx, fy, fxx, fxy, fyy)`.
fn derivatives(x: f64, y: f64) -> (f64, f64, f64, f64, f64) {
    use std::f64::consts::PI;
    let (a, b) = (PI / WIDTH, PI / DEPTH);
    let (sx, cx, sy, cy) = ((a * x).sin(), (a * x).cos(), (b * y).sin(), (b * y).cos());
    let r = (y - RIDGE_AT) / RIDGE_WIDTH;
    let g = RIDGE * (-r * r).exp();
    let gy = g * (-2.0 * r / RIDGE_WIDTH);
    let gyy = g * (4.0 * r * r - 2.0) / (RIDGE_WIDTH * RIDGE_WIDTH);
    (
        DOME * a * cx * sy,
        DOME * b * sx * cy + gy,
        -DOME * a * a * sx * sy,
        DOME * a * b * cx * cy,
        -DOME * b * b * sx * sy + gyy,
    )
}

/// The surface point over `(x, y)`.
pub fn point(x: f64, y: f64) -> DVec3 {
    DVec3::new(x, y, height(x, y))
}

/// The surface's unit normal over `(x, y)` (upwards).
pub fn normal(x: f64, y: f64) -> DVec3 {
    let (fx, fy, ..) = derivatives(x, y);
    DVec3::new(-fx, -fy, 1.0).normalize()
}

/// The surface's smallest radius of curvature over `(x, y)` (mm): its sharper principal
/// curvature, from the graph's first and second fundamental forms.
pub fn smallest_radius(x: f64, y: f64) -> f64 {
    let (fx, fy, fxx, fxy, fyy) = derivatives(x, y);
    let w = (1.0 + fx * fx + fy * fy).sqrt();
    let (e, f, g) = (1.0 + fx * fx, fx * fy, 1.0 + fy * fy);
    let (l, m, n) = (fxx / w, fxy / w, fyy / w);
    let det = e * g - f * f;
    let k = (l * n - m * m) / det;
    let h = (e * n - 2.0 * f * m + g * l) / (2.0 * det);
    let disc = (h * h - k).max(0.0).sqrt();
    let sharpest = (h.abs() + disc).max(1e-12);
    1.0 / sharpest
}

/// The distance from `p` to the nearest point of `surface`'s graph, nearly: the height
/// difference along the normal (exact to second order in the small slopes here).
pub fn distance_to_surface(p: DVec3) -> f64 {
    let d = p.z - height(p.x, p.y);
    (d * normal(p.x, p.y).z).abs()
}

/// A hole: a rounded rectangle of half-sizes `half` (along its own axes, turned by
/// `angle` rad) with corners of radius `radius` (a circle when both halves are the
/// radius, a slot when one is), centred at `centre`.
#[derive(Debug, Clone, Copy)]
pub struct Hole {
    pub centre: DVec2,
    pub half: DVec2,
    pub radius: f64,
    pub angle: f64,
}

impl Hole {
    pub fn circle(x: f64, y: f64, diameter: f64) -> Hole {
        let r = diameter / 2.0;
        Hole {
            centre: DVec2::new(x, y),
            half: DVec2::splat(r),
            radius: r,
            angle: 0.0,
        }
    }

    pub fn slot(x: f64, y: f64, length: f64, width: f64, angle_deg: f64) -> Hole {
        Hole {
            centre: DVec2::new(x, y),
            half: DVec2::new(length / 2.0, width / 2.0),
            radius: width / 2.0,
            angle: angle_deg.to_radians(),
        }
    }

    pub fn rounded(x: f64, y: f64, w: f64, h: f64, radius: f64) -> Hole {
        Hole {
            centre: DVec2::new(x, y),
            half: DVec2::new(w / 2.0, h / 2.0),
            radius,
            angle: 0.0,
        }
    }

    fn local(&self, p: DVec2) -> DVec2 {
        let d = p - self.centre;
        let (s, c) = self.angle.sin_cos();
        DVec2::new(c * d.x + s * d.y, -s * d.x + c * d.y)
    }

    fn global(&self, q: DVec2) -> DVec2 {
        let (s, c) = self.angle.sin_cos();
        self.centre + DVec2::new(c * q.x - s * q.y, s * q.x + c * q.y)
    }

    /// The signed distance from `p` to the outline (negative inside).
    pub fn signed_distance(&self, p: DVec2) -> f64 {
        let q = self.local(p).abs() - (self.half - DVec2::splat(self.radius));
        q.max(DVec2::ZERO).length() + q.x.max(q.y).min(0.0) - self.radius
    }

    /// How far across it is (mm).
    pub fn span(&self) -> f64 {
        2.0 * self.half.max_element()
    }

    /// The outline, points about `spacing` apart, counter-clockwise.
    pub fn outline(&self, spacing: f64) -> Vec<DVec2> {
        let inner = self.half - DVec2::splat(self.radius);
        let r = self.radius;
        // Four straight sides and four quarter arcs, walked counter-clockwise.
        let corners = [
            DVec2::new(inner.x, inner.y),
            DVec2::new(-inner.x, inner.y),
            DVec2::new(-inner.x, -inner.y),
            DVec2::new(inner.x, -inner.y),
        ];
        let mut out = Vec::new();
        for (k, &c) in corners.iter().enumerate() {
            let start = k as f64 * std::f64::consts::FRAC_PI_2;
            let arc = r * std::f64::consts::FRAC_PI_2;
            let steps = (arc / spacing).ceil().max(1.0) as usize;
            for s in 0..steps {
                let a = start + std::f64::consts::FRAC_PI_2 * s as f64 / steps as f64;
                out.push(self.global(c + r * DVec2::new(a.cos(), a.sin())));
            }
            // The straight side to the next corner's arc.
            let next = corners[(k + 1) % 4];
            let end = start + std::f64::consts::FRAC_PI_2;
            let from = c + r * DVec2::new(end.cos(), end.sin());
            let to = next + r * DVec2::new(end.cos(), end.sin());
            let length = from.distance(to);
            let steps = (length / spacing).round() as usize;
            for s in 0..steps {
                out.push(self.global(from.lerp(to, s as f64 / steps as f64)));
            }
        }
        out.dedup_by(|a, b| a.distance(*b) < 1e-9);
        out
    }
}

/// The holes of the test panel: circles of 10 to 80 mm, slots, rounded rectangles, one
/// 20 mm from the outer edge, three on the ridge (at y = 420), fourteen in all.
pub fn standard_holes() -> Vec<Hole> {
    vec![
        Hole::circle(120.0, 120.0, 10.0),
        Hole::circle(260.0, 150.0, 20.0),
        Hole::circle(420.0, 180.0, 40.0),
        Hole::circle(620.0, 200.0, 80.0),
        Hole::slot(820.0, 140.0, 80.0, 20.0, 30.0),
        Hole::slot(200.0, 300.0, 60.0, 12.0, 0.0),
        Hole::rounded(400.0, 300.0, 60.0, 40.0, 8.0),
        Hole::rounded(800.0, 310.0, 76.0, 30.0, 10.0),
        Hole::circle(40.0, 520.0, 30.0),
        Hole::circle(300.0, 420.0, 30.0),
        Hole::slot(520.0, 420.0, 70.0, 16.0, 0.0),
        Hole::rounded(700.0, 425.0, 50.0, 30.0, 6.0),
        Hole::circle(900.0, 540.0, 50.0),
        Hole::slot(160.0, 540.0, 50.0, 14.0, 90.0),
    ]
}

/// The closed outline `outline` added to `points`, its sides to `edges`.
fn add_loop(outline: Vec<DVec2>, points: &mut Vec<DVec2>, edges: &mut Vec<[usize; 2]>) {
    let first = points.len();
    let n = outline.len();
    points.extend(outline);
    for k in 0..n {
        edges.push([first + k, first + (k + 1) % n]);
    }
}

/// The outer edge, points about `spacing` apart, counter-clockwise.
fn outer_outline(spacing: f64) -> Vec<DVec2> {
    let corners = [
        DVec2::new(0.0, 0.0),
        DVec2::new(WIDTH, 0.0),
        DVec2::new(WIDTH, DEPTH),
        DVec2::new(0.0, DEPTH),
    ];
    let mut out = Vec::new();
    for k in 0..4 {
        let (a, b) = (corners[k], corners[(k + 1) % 4]);
        let steps = (a.distance(b) / spacing).round() as usize;
        for s in 0..steps {
            out.push(a.lerp(b, s as f64 / steps as f64));
        }
    }
    out
}

/// The panel meshed with elements about `spacing` long, its `holes` cut out.
pub fn panel(spacing: f64, holes: &[Hole]) -> Mesh {
    panel_with_crack(spacing, holes, None)
}

/// [`panel`], and where `crack` is `Some((x, gap))`, cut along the line `x` into two
/// patches as CAD exports them: the faces past the line on nodes of their own, moved
/// `gap` mm along x (a crack that width, node for node).
pub fn panel_with_crack(spacing: f64, holes: &[Hole], crack: Option<(f64, f64)>) -> Mesh {
    // The seam on a node of the outer edge's bottom and top.
    let step = WIDTH / (WIDTH / spacing).round();
    let crack = crack.map(|(x, gap)| ((x / step).round() * step, gap));
    let mut points: Vec<DVec2> = Vec::new();
    let mut edges: Vec<[usize; 2]> = Vec::new();
    add_loop(outer_outline(spacing), &mut points, &mut edges);
    if let Some((x, _)) = crack {
        // The seam: a constraint line across the panel, so no face straddles it.
        let steps = (DEPTH / spacing).round() as usize;
        let first = points.len();
        for s in 1..steps {
            points.push(DVec2::new(x, DEPTH * s as f64 / steps as f64));
        }
        let seam_end = |t: f64| {
            points
                .iter()
                .position(|q| (q.x - x).abs() < 1e-6 && (q.y - t).abs() < 1e-9)
                .expect("the outer edge has a node where the seam meets it")
        };
        let (bottom, top) = (seam_end(0.0), seam_end(DEPTH));
        let last = points.len() - 1;
        edges.push([bottom, first]);
        for k in first..last {
            edges.push([k, k + 1]);
        }
        edges.push([last, top]);
    }
    for h in holes {
        add_loop(h.outline(spacing), &mut points, &mut edges);
    }
    let clear = 0.5 * spacing;
    let row = spacing * 3f64.sqrt() / 2.0;
    let rows = (DEPTH / row).floor() as usize;
    for r in 0..=rows {
        let y = r as f64 * row;
        let mut x = if r % 2 == 0 { 0.0 } else { 0.5 * spacing };
        while x <= WIDTH {
            let q = DVec2::new(x, y);
            x += spacing;
            let inside_edge =
                q.x > clear && q.x < WIDTH - clear && q.y > clear && q.y < DEPTH - clear;
            let off_seam = crack.is_none_or(|(x, _)| (q.x - x).abs() > clear);
            if inside_edge && off_seam && holes.iter().all(|h| h.signed_distance(q) > clear) {
                points.push(q);
            }
        }
    }
    let spade_points: Vec<Point2<f64>> = points.iter().map(|q| Point2::new(q.x, q.y)).collect();
    let cdt: ConstrainedDelaunayTriangulation<Point2<f64>> =
        ConstrainedDelaunayTriangulation::bulk_load_cdt(spade_points, edges)
            .expect("the panel's outlines do not cross");
    let mut faces = Vec::new();
    for f in cdt.inner_faces() {
        let ids = f.vertices().map(|v| v.fix().index());
        let centre = (points[ids[0]] + points[ids[1]] + points[ids[2]]) / 3.0;
        let in_panel = centre.x > 0.0 && centre.x < WIDTH && centre.y > 0.0 && centre.y < DEPTH;
        if in_panel && holes.iter().all(|h| h.signed_distance(centre) > 0.0) {
            faces.push(Face::triangle(ids[0] as u32, ids[1] as u32, ids[2] as u32));
        }
    }
    let mut positions: Vec<DVec3> = points.iter().map(|q| point(q.x, q.y)).collect();
    if let Some((x, gap)) = crack {
        // The faces past the seam take copies of their nodes on it, moved by the gap
        // with every node past the seam.
        let mut copy: Vec<Option<u32>> = vec![None; positions.len()];
        for f in faces.iter_mut() {
            let ids: Vec<u32> = f.indices().to_vec();
            let centre = ids.iter().map(|&i| points[i as usize]).sum::<DVec2>() / 3.0;
            if centre.x <= x {
                continue;
            }
            let moved: Vec<u32> = ids
                .iter()
                .map(|&i| {
                    if (points[i as usize].x - x).abs() > 1e-9 {
                        return i;
                    }
                    *copy[i as usize].get_or_insert_with(|| {
                        positions.push(positions[i as usize]);
                        (positions.len() - 1) as u32
                    })
                })
                .collect();
            *f = Face::triangle(moved[0], moved[1], moved[2]);
        }
        let on_right: Vec<bool> = (0..positions.len())
            .map(|i| i >= points.len() || points[i].x > x + 1e-9)
            .collect();
        for (i, p) in positions.iter_mut().enumerate() {
            if on_right[i] {
                p.x += gap;
            }
        }
    }
    Mesh::new(positions, faces).expect("a valid panel")
}
