//! Pictures without a browser or a GPU: `dieface render`'s software rasterizer.
//!
//! A [`Picture`] is what to draw, in press coordinates (millimetres, Z up): shaded
//! triangle meshes ([`Shaded`]), each in one colour or with a colour per vertex
//! ([`Paint`]), polylines drawn over them ([`Polyline`]), and a [`Legend`] (names
//! beside colour swatches, or a colour scale with numbered ticks). [`render`] draws it
//! from a [`View`] onto a [`Canvas`] of a [`Size`] with an orthographic camera fitted to
//! everything drawn; [`encode_png`] makes the PNG file.
//!
//! [`scene_picture`] makes the picture of a tessellated [`Scene`]: each node in the
//! colour its kind has in the glTF export, curves (the punch opening, outlines, bead
//! lines) as lines on top, a swatch per kind. A distance picture (a later `diff`)
//! paints each vertex with [`distance_color`] and shows [`Legend::Scale`].
//!
//! Shading is Lambert's from a light at the eye, tilted a little up and to the left,
//! both sides of a sheet lit alike (die faces are open sheets), plus some ambient
//! light; colours are mixed in linear RGB and written as sRGB. The result is the same
//! bytes for the same picture: one thread, a fixed drawing order, fixed PNG settings.

pub mod camera;
pub mod colormap;
mod encode;
pub mod font;
pub mod raster;

use glam::DVec3;

pub use camera::{Camera, View};
pub use colormap::{distance_color, tick_label, ticks};
pub use encode::encode_png;
pub use raster::{Canvas, Linear, ScreenPoint};

use super::scene::{Geometry, Node, Scene};
use font::{draw_text, text_width, GLYPH_HEIGHT};
use raster::to_srgb;

/// The background: white, so every colour of a die face stands out from it.
pub const BACKGROUND: [u8; 3] = [255, 255, 255];
/// The colour of legend text and frames (sRGB).
const INK: [u8; 3] = [40, 40, 40];
/// Light that reaches every face whatever its slope (a fraction of the colour).
const AMBIENT: f64 = 0.30;
/// Most pixels a picture may have a side.
pub const MAX_SIDE: usize = 8192;
/// Most pixels a picture may have in all (32 megapixels: about 230 MB to draw).
pub const MAX_PIXELS: usize = 8192 * 4096;

/// A picture's size in pixels.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Size {
    /// Pixels across.
    pub width: usize,
    /// Pixels down.
    pub height: usize,
}

impl Default for Size {
    fn default() -> Size {
        Size {
            width: 1200,
            height: 900,
        }
    }
}

impl Size {
    /// Fewest pixels a side: a legend and a part still fit.
    pub const MIN_SIDE: usize = 16;

    /// Reads `WIDTHxHEIGHT` (`1200x900`), each side from [`Size::MIN_SIDE`] to
    /// [`MAX_SIDE`] and at most [`MAX_PIXELS`] in all; the message says what is wrong.
    pub fn parse(text: &str) -> Result<Size, String> {
        let form = "give the size as WIDTHxHEIGHT in pixels, e.g. 1200x900";
        let Some((w, h)) = text.trim().split_once(['x', 'X']) else {
            return Err(format!("no `x` between the width and the height; {form}"));
        };
        let side = |s: &str, what: &str| -> Result<usize, String> {
            let n: usize = s.trim().parse().map_err(|_| {
                format!("the {what} `{}` is not a whole number; {form}", abridged(s))
            })?;
            if !(Size::MIN_SIDE..=MAX_SIDE).contains(&n) {
                return Err(format!(
                    "the {what} must be from {} to {MAX_SIDE} pixels, not {n}",
                    Size::MIN_SIDE
                ));
            }
            Ok(n)
        };
        let size = Size {
            width: side(w, "width")?,
            height: side(h, "height")?,
        };
        if size.width * size.height > MAX_PIXELS {
            return Err(format!(
                "{}x{} is {} pixels, more than the {MAX_PIXELS} (32 megapixels) a picture may have",
                size.width,
                size.height,
                size.width * size.height
            ));
        }
        Ok(size)
    }
}

/// At most 20 characters of `s`, for quoting it in a message.
fn abridged(s: &str) -> String {
    let mut out: String = s.chars().take(20).collect();
    if s.chars().count() > 20 {
        out.push_str("...");
    }
    out
}

/// How a mesh is coloured.
#[derive(Debug, Clone, PartialEq)]
pub enum Paint {
    /// One colour (linear RGB) for the whole mesh.
    Uniform(Linear),
    /// A colour (linear RGB) per vertex, interpolated across each triangle: a value
    /// measured at the vertices, such as the distance to an earlier build.
    PerVertex(Vec<Linear>),
}

/// A triangle mesh to draw shaded.
#[derive(Debug, Clone, PartialEq)]
pub struct Shaded {
    /// Vertex positions, press millimetres.
    pub positions: Vec<DVec3>,
    /// Unit normals, one per position, for smooth shading; empty for flat shading
    /// (each triangle lit by its own normal).
    pub normals: Vec<DVec3>,
    /// Three indices per triangle (either winding; both sides are lit).
    pub indices: Vec<u32>,
    /// Its colours.
    pub paint: Paint,
}

/// A polyline drawn over the meshes (a curve: punch opening, outline, bead line).
#[derive(Debug, Clone, PartialEq)]
pub struct Polyline {
    /// The vertices in order, press millimetres.
    pub points: Vec<DVec3>,
    /// Its colour (linear RGB).
    pub color: Linear,
}

/// What the picture explains in its corner.
#[derive(Debug, Clone, PartialEq, Default)]
pub enum Legend {
    /// Nothing.
    #[default]
    None,
    /// A swatch of each colour with its name, top left.
    Swatches(Vec<(String, Linear)>),
    /// A colour bar of [`distance_color`] from 0 to `max`, right, with round values
    /// marked and labelled in `unit`, under a `title`.
    Scale {
        /// What the colours measure (`distance`).
        title: String,
        /// The unit of the values (`mm`).
        unit: String,
        /// The value at the top of the bar (red).
        max: f64,
    },
}

/// Everything a picture shows.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Picture {
    /// Shaded meshes, drawn first.
    pub meshes: Vec<Shaded>,
    /// Lines, drawn over the meshes where they are not hidden behind one.
    pub lines: Vec<Polyline>,
    /// The legend.
    pub legend: Legend,
}

impl Picture {
    /// Whether there is no triangle and no line to draw.
    pub fn is_empty(&self) -> bool {
        self.meshes.iter().all(|m| m.indices.len() < 3)
            && self.lines.iter().all(|l| l.points.len() < 2)
    }

    /// Every point drawn (what the camera is fitted to).
    fn points(&self) -> impl Iterator<Item = DVec3> + '_ {
        let meshes = self.meshes.iter().flat_map(|m| {
            m.indices
                .iter()
                .filter_map(|&i| m.positions.get(i as usize).copied())
        });
        let lines = self
            .lines
            .iter()
            .filter(|l| l.points.len() >= 2)
            .flat_map(|l| l.points.iter().copied());
        meshes.chain(lines)
    }
}

/// The picture of a tessellated scene: every node's triangles in its kind's colour (the
/// glTF material's), its line strips in that colour darkened, and a swatch per kind
/// labelled with the kind and its declarations (`blankholder binder`).
pub fn scene_picture(scene: &Scene) -> Picture {
    let mut picture = Picture::default();
    // Kinds in order of first appearance, each with its colour and declarations.
    let mut kinds: Vec<(String, Linear, Vec<String>)> = Vec::new();
    for top in &scene.nodes {
        let mut drawn = false;
        let mut color = top.color;
        for node in top.walk() {
            for g in node.primitives() {
                drawn = true;
                color = node.color;
                add_geometry(&mut picture, node, g);
            }
        }
        if !drawn {
            continue;
        }
        match kinds.iter_mut().find(|(k, _, _)| *k == top.kind) {
            Some((_, _, names)) => names.push(top.name.clone()),
            None => kinds.push((top.kind.clone(), color, vec![top.name.clone()])),
        }
    }
    picture.legend = Legend::Swatches(
        kinds
            .into_iter()
            .map(|(kind, color, names)| (swatch_label(&kind, &names), color))
            .collect(),
    );
    picture
}

/// A legend line: the kind, then its declarations, cut at 30 characters.
fn swatch_label(kind: &str, names: &[String]) -> String {
    let text = format!("{kind} {}", names.join(", "));
    if text.chars().count() <= 30 {
        return text;
    }
    let mut cut: String = text.chars().take(27).collect();
    cut.push_str("...");
    cut
}

/// One scene primitive added to the picture in the node's colour.
fn add_geometry(picture: &mut Picture, node: &Node, g: &Geometry) {
    match g {
        Geometry::Triangles {
            positions,
            normals,
            indices,
            ..
        } => picture.meshes.push(Shaded {
            positions: positions.clone(),
            normals: normals.clone(),
            indices: indices.clone(),
            paint: Paint::Uniform(node.color),
        }),
        Geometry::LineStrip { points } => picture.lines.push(Polyline {
            points: points.clone(),
            color: node.color.map(|c| c * LINE_SHADE),
        }),
    }
}

/// How much darker a curve is drawn than its kind's colour, so it stands out on a
/// surface of the same kind (and a plain grey curve on the white background).
const LINE_SHADE: f64 = 0.45;

/// Draws `picture` from `view` on a canvas of `size`: the camera fitted to every mesh
/// and line with a 5 % margin (beside the legend), meshes shaded with depth, lines over
/// them, then the legend.
pub fn render(picture: &Picture, view: View, size: Size) -> Canvas {
    let mut canvas = Canvas::new(size.width, size.height, BACKGROUND);
    let text_scale = (size.width.min(size.height) / 450).max(1);
    let camera = fit_beside_legend(picture, view, size, text_scale);
    if let Some(camera) = &camera {
        draw_meshes(&mut canvas, picture, camera);
        draw_lines(&mut canvas, picture, camera, size);
    }
    let reserved = legend_width(&picture.legend, text_scale)
        .filter(|lw| (*lw as f64) < LEGEND_SHARE * size.width as f64);
    if reserved.is_some() {
        match &picture.legend {
            Legend::None => {}
            Legend::Swatches(items) => draw_swatches(&mut canvas, items, text_scale),
            Legend::Scale { title, unit, max } => {
                draw_scale(&mut canvas, title, unit, *max, text_scale)
            }
        }
    }
    canvas
}

/// The most of the picture's width a legend may take; a wider one is left out.
const LEGEND_SHARE: f64 = 0.45;

/// The camera of `view` fitted to the picture, clear of the legend: a scale's column
/// on the right is always kept free; swatches (top left) are kept clear of only when
/// the part would run into them, by fitting it beside or below them, whichever draws
/// it larger.
fn fit_beside_legend(picture: &Picture, view: View, size: Size, scale: usize) -> Option<Camera> {
    let (w, h) = (size.width as f64, size.height as f64);
    let fit = |area| Camera::fit(view, picture.points(), area, 0.05);
    let Some(lw) =
        legend_width(&picture.legend, scale).filter(|lw| (*lw as f64) < LEGEND_SHARE * w)
    else {
        return fit((0.0, 0.0, w, h));
    };
    let lw = lw as f64;
    match &picture.legend {
        Legend::Scale { .. } => fit((0.0, 0.0, w - lw, h)),
        Legend::Swatches(items) => {
            let lh = (2 * pad(scale) + items.len() * row_height(scale)) as f64;
            let whole = fit((0.0, 0.0, w, h))?;
            let (left, top, _, _) = whole.drawn();
            if left >= lw || top >= lh || lh >= 0.5 * h {
                return Some(whole);
            }
            let beside = fit((lw, 0.0, w - lw, h))?;
            let below = fit((0.0, lh, w, h - lh))?;
            Some(if below.scale >= beside.scale {
                below
            } else {
                beside
            })
        }
        Legend::None => fit((0.0, 0.0, w, h)),
    }
}

/// The light's direction (towards the light): from the eye, tilted a little up and to
/// the left, so faces square to the view are lit almost fully and slopes show.
fn light(camera: &Camera) -> DVec3 {
    (-camera.forward + 0.35 * camera.up - 0.25 * camera.right).normalize()
}

/// A colour lit on a face with unit normal `n` (either side).
fn shade(color: Linear, n: DVec3, light: DVec3) -> Linear {
    let lambert = if n.is_finite() {
        n.dot(light).abs().min(1.0)
    } else {
        1.0
    };
    let k = AMBIENT + (1.0 - AMBIENT) * lambert;
    color.map(|c| c * k)
}

/// Every mesh's triangles, shaded per vertex (Gouraud) or per face.
fn draw_meshes(canvas: &mut Canvas, picture: &Picture, camera: &Camera) {
    let light = light(camera);
    for mesh in &picture.meshes {
        let n = mesh.positions.len();
        let screen: Vec<ScreenPoint> = mesh.positions.iter().map(|&p| camera.project(p)).collect();
        let smooth = mesh.normals.len() == n;
        let color_of = |i: usize| match &mesh.paint {
            Paint::Uniform(c) => *c,
            Paint::PerVertex(cs) => cs.get(i).copied().unwrap_or(colormap::MISSING),
        };
        for tri in mesh.indices.chunks_exact(3) {
            let idx = [tri[0] as usize, tri[1] as usize, tri[2] as usize];
            if idx.iter().any(|&i| i >= n) {
                continue;
            }
            let p = idx.map(|i| screen[i]);
            if p.iter()
                .any(|q| !(q.x.is_finite() && q.y.is_finite() && q.depth.is_finite()))
            {
                continue;
            }
            let colors = if smooth {
                idx.map(|i| shade(color_of(i), mesh.normals[i], light))
            } else {
                let [a, b, c] = idx.map(|i| mesh.positions[i]);
                let normal = (b - a).cross(c - a).normalize_or_zero();
                idx.map(|i| shade(color_of(i), normal, light))
            };
            canvas.triangle(p, colors);
        }
    }
}

/// Every polyline, over the meshes: 2 px wide on pictures 800 px or more across,
/// drawn where it lies on or in front of a surface (a bias of two pixels' worth of
/// depth, so a curve on a sloping surface is not lost in its triangles).
fn draw_lines(canvas: &mut Canvas, picture: &Picture, camera: &Camera, size: Size) {
    let width = if size.width.min(size.height) >= 800 {
        2
    } else {
        1
    };
    let bias = 2.0 / camera.scale;
    for line in &picture.lines {
        let screen: Vec<ScreenPoint> = line.points.iter().map(|&p| camera.project(p)).collect();
        for pair in screen.windows(2) {
            canvas.line(pair[0], pair[1], width, line.color, bias);
        }
    }
}

/// Canvas pixels between the legend and the picture's edge.
fn pad(scale: usize) -> usize {
    8 * scale
}

/// Height of one legend row.
fn row_height(scale: usize) -> usize {
    (GLYPH_HEIGHT + 4) * scale
}

/// The width the legend takes, or `None` when there is none.
fn legend_width(legend: &Legend, scale: usize) -> Option<usize> {
    match legend {
        Legend::None => None,
        Legend::Swatches(items) if items.is_empty() => None,
        Legend::Swatches(items) => {
            let text = items
                .iter()
                .map(|(t, _)| text_width(t, scale))
                .max()
                .unwrap_or(0);
            Some(2 * pad(scale) + swatch_size(scale) + 4 * scale + text)
        }
        Legend::Scale { title, unit, max } => {
            let labels = ticks(*max, 5)
                .iter()
                .map(|v| text_width(&format!("{} {unit}", tick_label(*v)), scale))
                .chain([text_width(title, scale)])
                .max()
                .unwrap_or(0);
            Some(2 * pad(scale) + BAR_WIDTH * scale + 4 * scale + labels)
        }
    }
}

/// Side of a legend swatch.
fn swatch_size(scale: usize) -> usize {
    7 * scale
}

/// Width of the colour bar of a scale, in font pixels.
const BAR_WIDTH: usize = 6;

/// The swatches, top left: a square of each colour (as a face square to the view is
/// lit) framed in ink, and its label.
fn draw_swatches(canvas: &mut Canvas, items: &[(String, Linear)], scale: usize) {
    let (x0, mut y) = (pad(scale) as i64, pad(scale) as i64);
    let s = swatch_size(scale) as i64;
    let full = DVec3::new(-0.25, 0.35, 1.0).normalize().z;
    for (label, color) in items {
        let fill = to_srgb(color.map(|c| c * (AMBIENT + (1.0 - AMBIENT) * full)));
        for dy in 0..s {
            for dx in 0..s {
                let edge = dx == 0 || dy == 0 || dx == s - 1 || dy == s - 1;
                canvas.put(x0 + dx, y + dy, if edge { INK } else { fill });
            }
        }
        draw_text(canvas, x0 + s + 4 * scale as i64, y, label, scale, INK);
        y += row_height(scale) as i64;
    }
}

/// The colour scale, right: its title, a bar from 0 (bottom) to `max` (top) in
/// [`distance_color`], and a tick with its value at each round number.
fn draw_scale(canvas: &mut Canvas, title: &str, unit: &str, max: f64, scale: usize) {
    let width = canvas.width() as i64;
    let height = canvas.height() as i64;
    let Some(legend) = legend_width(
        &Legend::Scale {
            title: title.into(),
            unit: unit.into(),
            max,
        },
        scale,
    ) else {
        return;
    };
    let x0 = width - legend as i64 + pad(scale) as i64;
    let top = pad(scale) as i64 + row_height(scale) as i64 * 2;
    let bottom = height - pad(scale) as i64 - row_height(scale) as i64;
    draw_text(canvas, x0, pad(scale) as i64, title, scale, INK);
    if bottom - top < 2 {
        return;
    }
    let bar = (BAR_WIDTH * scale) as i64;
    for y in top..=bottom {
        let t = (bottom - y) as f64 / (bottom - top) as f64;
        let c = to_srgb(distance_color(t * max, max));
        for x in x0..x0 + bar {
            canvas.put(x, y, c);
        }
    }
    let half_glyph = (GLYPH_HEIGHT * scale / 2) as i64;
    for v in ticks(max, 5) {
        let y = bottom - ((v / max) * (bottom - top) as f64).round() as i64;
        for x in x0 + bar..x0 + bar + 3 * scale as i64 {
            canvas.put(x, y, INK);
        }
        let label = format!("{} {unit}", tick_label(v));
        draw_text(
            canvas,
            x0 + bar + 4 * scale as i64,
            y - half_glyph,
            &label,
            scale,
            INK,
        );
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn square(z: f64, paint: Paint) -> Shaded {
        Shaded {
            positions: vec![
                DVec3::new(0.0, 0.0, z),
                DVec3::new(10.0, 0.0, z),
                DVec3::new(10.0, 10.0, z),
                DVec3::new(0.0, 10.0, z),
            ],
            normals: Vec::new(),
            indices: vec![0, 1, 2, 0, 2, 3],
            paint,
        }
    }

    #[test]
    fn sizes_are_read_and_bad_ones_explained() {
        assert_eq!(
            Size::parse("640x480"),
            Ok(Size {
                width: 640,
                height: 480
            })
        );
        assert_eq!(
            Size::parse(" 100X200 "),
            Ok(Size {
                width: 100,
                height: 200
            })
        );
        for bad in [
            "640",
            "x480",
            "640x",
            "-5x10",
            "10x10",
            "9000x100",
            "8192x8192",
            "1.5x20",
        ] {
            assert!(Size::parse(bad).is_err(), "{bad}");
        }
        assert!(Size::parse("abc").unwrap_err().contains("WIDTHxHEIGHT"));
    }

    #[test]
    fn the_top_view_shows_the_nearer_of_two_squares_in_its_colour() {
        let red = [0.8, 0.0, 0.0];
        let blue = [0.0, 0.0, 0.8];
        let picture = Picture {
            meshes: vec![
                square(0.0, Paint::Uniform(blue)),
                square(5.0, Paint::Uniform(red)),
            ],
            lines: Vec::new(),
            legend: Legend::None,
        };
        let size = Size {
            width: 40,
            height: 40,
        };
        let c = render(&picture, View::Top, size);
        let mid = c.pixel(20, 20).expect("inside");
        assert!(
            mid[0] > 150 && mid[2] == 0,
            "the upper square is red: {mid:?}"
        );
        assert_eq!(c.pixel(0, 0), Some(BACKGROUND));
        let c = render(&picture, View::Bottom, size);
        let mid = c.pixel(20, 20).expect("inside");
        assert!(
            mid[2] > 150 && mid[0] == 0,
            "from below, the blue one: {mid:?}"
        );
    }

    #[test]
    fn per_vertex_paint_is_interpolated_and_a_scale_is_drawn() {
        let colors = [0.0, 0.0, 1.0, 1.0]
            .map(|d| distance_color(d, 1.0))
            .to_vec();
        let picture = Picture {
            meshes: vec![square(0.0, Paint::PerVertex(colors))],
            lines: Vec::new(),
            legend: Legend::Scale {
                title: "distance".into(),
                unit: "mm".into(),
                max: 1.0,
            },
        };
        let c = render(
            &picture,
            View::Top,
            Size {
                width: 400,
                height: 200,
            },
        );
        // The square's bottom (y = 0) is blue, its top (y = 10) red.
        let column: Vec<[u8; 3]> = (0..200)
            .filter_map(|y| c.pixel(100, y))
            .filter(|p| *p != BACKGROUND)
            .collect();
        let (first, last) = (
            column.first().expect("drawn"),
            column.last().expect("drawn"),
        );
        assert!(first[0] > first[2], "top of the page red: {first:?}");
        assert!(last[2] > last[0], "bottom blue: {last:?}");
        // The bar (legend 74 px wide: 8 px pad, then the 6 px bar from x = 334) runs
        // from the scale's red at its top (y = 32) to blue at its bottom (y = 180).
        assert_eq!(c.pixel(336, 32), Some(to_srgb(colormap::HIGH)));
        assert_eq!(c.pixel(336, 180), Some(to_srgb(colormap::LOW)));
        let tick_labels = (340..400).flat_map(|x| (20..200).map(move |y| (x, y)));
        let ink = tick_labels
            .filter(|&(x, y)| c.pixel(x, y) == Some(INK))
            .count();
        assert!(ink > 100, "ticks and labels drawn: {ink}");
    }

    #[test]
    fn the_same_picture_gives_the_same_bytes() {
        let picture = Picture {
            meshes: vec![square(0.0, Paint::Uniform([0.5, 0.5, 0.2]))],
            lines: vec![Polyline {
                points: vec![DVec3::ZERO, DVec3::new(10.0, 10.0, 0.0)],
                color: [0.0; 3],
            }],
            legend: Legend::Swatches(vec![("product panel".into(), [0.5, 0.5, 0.2])]),
        };
        let a = encode_png(&render(&picture, View::Iso, Size::default())).expect("encodes");
        let b = encode_png(&render(&picture, View::Iso, Size::default())).expect("encodes");
        assert_eq!(a, b);
    }
}
