//! The software rasterizer: an RGB canvas with a depth buffer, triangles filled with
//! colours interpolated across them, and lines drawn over them.
//!
//! Everything runs on one thread in a fixed order, so the same calls give the same
//! pixels on every run (the pictures are compared byte for byte). Pixel `(x, y)` has
//! its centre at `(x + 0.5, y + 0.5)`, `y` growing downwards; a pixel is covered by a
//! triangle when its centre lies inside, and a centre on an edge is given to exactly
//! one of the two triangles sharing it (the top-left rule), so a mesh has neither gaps
//! nor doubly drawn seams. Depth grows away from the eye: the smaller depth wins.

/// A point on the canvas: `x`, `y` in pixels, `depth` along the view (smaller is
/// nearer).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ScreenPoint {
    /// Pixels from the left edge.
    pub x: f64,
    /// Pixels from the top edge.
    pub y: f64,
    /// Distance along the view direction (any unit; smaller is nearer).
    pub depth: f64,
}

/// A colour while drawing: linear RGB, each channel in `0..=1`.
pub type Linear = [f64; 3];

/// The picture being drawn: 8-bit sRGB pixels, row by row from the top, and the depth
/// of what each pixel shows.
#[derive(Debug, Clone)]
pub struct Canvas {
    width: usize,
    height: usize,
    /// `3 * width * height` bytes, sRGB.
    rgb: Vec<u8>,
    /// One depth per pixel; `f32::INFINITY` where nothing is drawn yet.
    depth: Vec<f32>,
}

impl Canvas {
    /// A `width` x `height` canvas filled with `background` (sRGB bytes), its depth
    /// empty.
    pub fn new(width: usize, height: usize, background: [u8; 3]) -> Canvas {
        let n = width * height;
        let mut rgb = Vec::with_capacity(3 * n);
        for _ in 0..n {
            rgb.extend_from_slice(&background);
        }
        Canvas {
            width,
            height,
            rgb,
            depth: vec![f32::INFINITY; n],
        }
    }

    /// Width in pixels.
    pub fn width(&self) -> usize {
        self.width
    }

    /// Height in pixels.
    pub fn height(&self) -> usize {
        self.height
    }

    /// The sRGB pixels, `3 * width * height` bytes, row by row from the top.
    pub fn pixels(&self) -> &[u8] {
        &self.rgb
    }

    /// The pixel at `(x, y)` (sRGB), or `None` outside the canvas.
    pub fn pixel(&self, x: usize, y: usize) -> Option<[u8; 3]> {
        if x >= self.width || y >= self.height {
            return None;
        }
        let i = 3 * (y * self.width + x);
        Some([self.rgb[i], self.rgb[i + 1], self.rgb[i + 2]])
    }

    /// The depth drawn at `(x, y)` (`INFINITY` where nothing is), or `None` outside.
    pub fn depth(&self, x: usize, y: usize) -> Option<f32> {
        (x < self.width && y < self.height).then(|| self.depth[y * self.width + x])
    }

    /// Sets a pixel to an sRGB colour regardless of depth (legends, text), inside the
    /// canvas only.
    pub fn put(&mut self, x: i64, y: i64, color: [u8; 3]) {
        if x < 0 || y < 0 || x >= self.width as i64 || y >= self.height as i64 {
            return;
        }
        let i = 3 * (y as usize * self.width + x as usize);
        self.rgb[i..i + 3].copy_from_slice(&color);
    }

    /// Draws the pixel at `(x, y)` in `color` if `depth` is nearer than what it shows.
    fn plot(&mut self, x: usize, y: usize, depth: f64, color: Linear) {
        let i = y * self.width + x;
        let d = depth as f32;
        if d < self.depth[i] {
            self.depth[i] = d;
            self.rgb[3 * i..3 * i + 3].copy_from_slice(&to_srgb(color));
        }
    }

    /// Fills the triangle `p` with the colours `c` at its corners interpolated across
    /// it (barycentric in screen space: the camera is orthographic, so this is exact),
    /// keeping at each pixel the nearest surface drawn so far. Either winding; a
    /// triangle seen edge-on covers nothing.
    pub fn triangle(&mut self, p: [ScreenPoint; 3], c: [Linear; 3]) {
        let area = edge(p[0], p[1], p[2].x, p[2].y);
        if area == 0.0 || !area.is_finite() {
            return;
        }
        // Wound so the area is positive: edges then have the inside on their left.
        let (p, c) = if area < 0.0 {
            ([p[0], p[2], p[1]], [c[0], c[2], c[1]])
        } else {
            (p, c)
        };
        let area = area.abs();
        let min_x = p.iter().map(|q| q.x).fold(f64::INFINITY, f64::min);
        let max_x = p.iter().map(|q| q.x).fold(f64::NEG_INFINITY, f64::max);
        let min_y = p.iter().map(|q| q.y).fold(f64::INFINITY, f64::min);
        let max_y = p.iter().map(|q| q.y).fold(f64::NEG_INFINITY, f64::max);
        // The pixels whose centres may lie inside, clipped to the canvas.
        let x0 = (min_x - 0.5).ceil().max(0.0);
        let x1 = (max_x - 0.5).floor().min(self.width as f64 - 1.0);
        let y0 = (min_y - 0.5).ceil().max(0.0);
        let y1 = (max_y - 0.5).floor().min(self.height as f64 - 1.0);
        if x0 > x1 || y0 > y1 {
            return;
        }
        // Edge k is the one opposite corner k; `owns[k]` says whether a centre exactly
        // on it is inside (top-left rule).
        let owns = [
            top_left(p[1], p[2]),
            top_left(p[2], p[0]),
            top_left(p[0], p[1]),
        ];
        let edges = [(p[1], p[2]), (p[2], p[0]), (p[0], p[1])];
        for y in y0 as usize..=y1 as usize {
            let cy = y as f64 + 0.5;
            // The row's run of centres inside, from the three edges' half-planes (a
            // pixel of slack each side; the exact test below decides), so a long thin
            // triangle is not scanned across its whole bounding box.
            let (mut lo, mut hi) = (x0, x1);
            for (a, b) in edges {
                let slope = a.y - b.y; // d(edge)/dx
                let at_zero = (b.x - a.x) * (cy - a.y) + (b.y - a.y) * a.x;
                if slope > 0.0 {
                    lo = lo.max((-at_zero / slope - 0.5).floor() - 1.0);
                } else if slope < 0.0 {
                    hi = hi.min((-at_zero / slope - 0.5).ceil() + 1.0);
                }
            }
            if lo > hi {
                continue;
            }
            for x in lo as usize..=hi as usize {
                let cx = x as f64 + 0.5;
                let w = [
                    edge(p[1], p[2], cx, cy),
                    edge(p[2], p[0], cx, cy),
                    edge(p[0], p[1], cx, cy),
                ];
                let inside = (0..3).all(|k| w[k] > 0.0 || (w[k] == 0.0 && owns[k]));
                if !inside {
                    continue;
                }
                let b = [w[0] / area, w[1] / area, w[2] / area];
                let depth = b[0] * p[0].depth + b[1] * p[1].depth + b[2] * p[2].depth;
                let color =
                    std::array::from_fn(|ch| b[0] * c[0][ch] + b[1] * c[1][ch] + b[2] * c[2][ch]);
                self.plot(x, y, depth, color);
            }
        }
    }

    /// Draws the segment from `a` to `b`, `width` pixels wide (1 or more), in `color`,
    /// where it is nearer than what is drawn by `bias` (a line lying on a surface is
    /// drawn over it: give a bias a little larger than the tessellation's sag in
    /// depth units).
    pub fn line(&mut self, a: ScreenPoint, b: ScreenPoint, width: usize, color: Linear, bias: f64) {
        let (dx, dy) = (b.x - a.x, b.y - a.y);
        let steps = dx.abs().max(dy.abs()).ceil();
        if !steps.is_finite() || steps > 1e6 {
            return;
        }
        let steps = steps.max(1.0) as usize;
        let width = width.max(1) as i64;
        let half = (width - 1) / 2;
        for s in 0..=steps {
            let t = s as f64 / steps as f64;
            let x = (a.x + t * dx).floor() as i64;
            let y = (a.y + t * dy).floor() as i64;
            let depth = a.depth + t * (b.depth - a.depth) - bias;
            for oy in 0..width {
                for ox in 0..width {
                    let (px, py) = (x + ox - half, y + oy - half);
                    if px >= 0
                        && py >= 0
                        && (px as usize) < self.width
                        && (py as usize) < self.height
                    {
                        self.plot(px as usize, py as usize, depth, color);
                    }
                }
            }
        }
    }
}

/// Twice the signed area of `(a, b, (x, y))`: positive when the point lies on the left
/// of `a -> b` in screen axes (y down), i.e. clockwise as seen on the screen.
fn edge(a: ScreenPoint, b: ScreenPoint, x: f64, y: f64) -> f64 {
    (b.x - a.x) * (y - a.y) - (b.y - a.y) * (x - a.x)
}

/// Whether the edge `a -> b` of a positively wound triangle is a top or a left edge,
/// whose centres count as inside.
fn top_left(a: ScreenPoint, b: ScreenPoint) -> bool {
    let (dx, dy) = (b.x - a.x, b.y - a.y);
    // With y down and positive area, a top edge runs left to right (dy == 0, dx > 0)
    // and a left edge runs upwards (dy < 0).
    (dy == 0.0 && dx > 0.0) || dy < 0.0
}

/// A linear RGB colour as sRGB bytes (clamped to `0..=1` first; NaN as black).
pub fn to_srgb(c: Linear) -> [u8; 3] {
    c.map(|v| {
        let v = if v.is_nan() { 0.0 } else { v.clamp(0.0, 1.0) };
        let s = if v <= 0.003_130_8 {
            12.92 * v
        } else {
            1.055 * v.powf(1.0 / 2.4) - 0.055
        };
        (s * 255.0 + 0.5).floor().clamp(0.0, 255.0) as u8
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn at(x: f64, y: f64, depth: f64) -> ScreenPoint {
        ScreenPoint { x, y, depth }
    }

    const WHITE: [u8; 3] = [255, 255, 255];

    fn covered(c: &Canvas) -> Vec<(usize, usize)> {
        let mut out = Vec::new();
        for y in 0..c.height() {
            for x in 0..c.width() {
                if c.pixel(x, y) != Some(WHITE) {
                    out.push((x, y));
                }
            }
        }
        out
    }

    #[test]
    fn a_triangle_covers_the_pixels_whose_centres_lie_inside() {
        // The right triangle with legs of 7.9 px covers the centres (i + .5, j + .5)
        // with i + j + 1 < 7.9: i + j <= 6, 28 pixels.
        for flip in [false, true] {
            let mut c = Canvas::new(10, 10, WHITE);
            let (a, b, d) = (at(0.0, 0.0, 1.0), at(7.9, 0.0, 1.0), at(0.0, 7.9, 1.0));
            let corners = if flip { [a, d, b] } else { [a, b, d] };
            c.triangle(corners, [[0.0; 3]; 3]);
            let expected: Vec<(usize, usize)> = (0..10)
                .flat_map(|y| (0..10).map(move |x| (x, y)))
                .filter(|&(x, y)| x + y <= 6)
                .collect();
            assert_eq!(covered(&c), expected, "flip {flip}");
        }
    }

    #[test]
    fn two_triangles_sharing_an_edge_cover_each_centre_once() {
        // A 4 x 4 square split on its diagonal, whose centres lie on the shared edge:
        // each pixel drawn by exactly one triangle (counted through the depth written).
        let mut c = Canvas::new(4, 4, WHITE);
        let (p00, p40, p04, p44) = (
            at(0.0, 0.0, 1.0),
            at(4.0, 0.0, 1.0),
            at(0.0, 4.0, 1.0),
            at(4.0, 4.0, 1.0),
        );
        c.triangle([p00, p40, p44], [[1.0, 0.0, 0.0]; 3]);
        let first = covered(&c).len();
        c.triangle([p00, p44, p04], [[0.0, 0.0, 1.0]; 3]);
        let reds = (0..16)
            .filter(|i| c.pixel(i % 4, i / 4) == Some([255, 0, 0]))
            .count();
        let blues = (0..16)
            .filter(|i| c.pixel(i % 4, i / 4) == Some([0, 0, 255]))
            .count();
        assert_eq!(
            reds, first,
            "the second triangle drew over none of the first"
        );
        assert_eq!(reds + blues, 16, "no gap");
    }

    #[test]
    fn the_depth_buffer_keeps_the_nearer_triangle_whichever_comes_first() {
        let big = |d| [at(0.0, 0.0, d), at(8.0, 0.0, d), at(0.0, 8.0, d)];
        for near_first in [true, false] {
            let mut c = Canvas::new(8, 8, WHITE);
            let (near, far) = ((big(1.0), [1.0, 0.0, 0.0]), (big(2.0), [0.0, 0.0, 1.0]));
            let order = if near_first { [near, far] } else { [far, near] };
            for (p, col) in order {
                c.triangle(p, [col; 3]);
            }
            assert_eq!(c.pixel(1, 1), Some([255, 0, 0]), "near first: {near_first}");
            assert_eq!(c.depth(1, 1), Some(1.0));
        }
    }

    #[test]
    fn colours_are_interpolated_from_the_corners() {
        let mut c = Canvas::new(9, 9, WHITE);
        c.triangle(
            [at(0.0, 0.0, 0.0), at(9.0, 0.0, 0.0), at(0.0, 9.0, 0.0)],
            [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
        );
        let near_red = c.pixel(0, 0).expect("inside");
        let near_green = c.pixel(7, 0).expect("inside");
        assert!(near_red[0] > 200 && near_red[1] < 150, "{near_red:?}");
        assert!(near_green[1] > 200 && near_green[0] < 150, "{near_green:?}");
    }

    #[test]
    fn lines_are_drawn_over_a_surface_they_lie_on_and_hidden_behind_a_nearer_one() {
        let mut c = Canvas::new(10, 10, WHITE);
        c.triangle(
            [at(0.0, 0.0, 5.0), at(20.0, 0.0, 5.0), at(0.0, 20.0, 5.0)],
            [[0.0; 3]; 3],
        );
        c.line(
            at(0.0, 2.5, 5.0),
            at(10.0, 2.5, 5.0),
            1,
            [1.0, 0.0, 0.0],
            0.01,
        );
        assert_eq!(c.pixel(3, 2), Some([255, 0, 0]), "on the surface: drawn");
        c.line(
            at(0.0, 6.5, 9.0),
            at(4.0, 6.5, 9.0),
            1,
            [0.0, 0.0, 1.0],
            0.01,
        );
        assert_eq!(c.pixel(1, 6), Some([0, 0, 0]), "behind the surface: hidden");
    }

    #[test]
    fn srgb_conversion_keeps_the_ends_and_brightens_the_middle() {
        assert_eq!(to_srgb([0.0, 1.0, 0.5]), [0, 255, 188]);
        assert_eq!(to_srgb([-1.0, 2.0, f64::NAN]), [0, 255, 0]);
    }
}
