//! The views a picture is drawn from and the orthographic camera fitted to what it
//! shows.
//!
//! Press coordinates: millimetres, Z up (the press stroke), the die's front at -Y.

use glam::DVec3;

use super::raster::ScreenPoint;

/// Where the picture is seen from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum View {
    /// From the front, the right and above (press `(1, -1, 1)`), Z up on the page.
    #[default]
    Iso,
    /// From above, looking down -Z: X to the right, Y up the page.
    Top,
    /// From below, looking up +Z: X to the left, Y up the page.
    Bottom,
    /// From the front (-Y), looking along +Y: X to the right, Z up.
    Front,
    /// From the back (+Y), looking along -Y: X to the left, Z up.
    Back,
    /// From the right (+X), looking along -X: Y to the right, Z up.
    Side,
}

impl View {
    /// Every view with its name on the command line.
    pub const ALL: [(&'static str, View); 6] = [
        ("iso", View::Iso),
        ("top", View::Top),
        ("front", View::Front),
        ("side", View::Side),
        ("back", View::Back),
        ("bottom", View::Bottom),
    ];

    /// The view named `name` (`iso`, `top`, ...), or `None`.
    pub fn from_name(name: &str) -> Option<View> {
        Self::ALL.iter().find(|(n, _)| *n == name).map(|&(_, v)| v)
    }

    /// The direction the camera looks in and the direction that is up on the page.
    fn axes(self) -> (DVec3, DVec3) {
        match self {
            View::Iso => (DVec3::new(-1.0, 1.0, -1.0).normalize(), DVec3::Z),
            View::Top => (DVec3::NEG_Z, DVec3::Y),
            View::Bottom => (DVec3::Z, DVec3::Y),
            View::Front => (DVec3::Y, DVec3::Z),
            View::Back => (DVec3::NEG_Y, DVec3::Z),
            View::Side => (DVec3::NEG_X, DVec3::Z),
        }
    }
}

/// An orthographic camera: press points to canvas pixels and depth.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Camera {
    /// Into the picture (unit).
    pub forward: DVec3,
    /// To the right on the page (unit).
    pub right: DVec3,
    /// Up the page (unit).
    pub up: DVec3,
    /// The press point drawn at the centre of the fitted area.
    center: DVec3,
    /// Pixels per millimetre.
    pub scale: f64,
    /// The canvas pixel the centre is drawn at.
    origin: (f64, f64),
    /// Half the drawn width and height, in pixels.
    half: (f64, f64),
}

impl Camera {
    /// The camera of `view` that fits every point of `points` into the rectangle
    /// `area` (`x`, `y`, width, height in pixels), centred, with `margin` of the
    /// rectangle's smaller side left free all round (0.05: 5 %). `None` when there is
    /// no finite point.
    pub fn fit(
        view: View,
        points: impl Iterator<Item = DVec3>,
        area: (f64, f64, f64, f64),
        margin: f64,
    ) -> Option<Camera> {
        let (forward, up_hint) = view.axes();
        let right = forward.cross(up_hint).normalize();
        let up = right.cross(forward);
        let mut lo = DVec3::INFINITY;
        let mut hi = DVec3::NEG_INFINITY;
        for p in points.filter(|p| p.is_finite()) {
            let q = DVec3::new(p.dot(right), p.dot(up), p.dot(forward));
            lo = lo.min(q);
            hi = hi.max(q);
        }
        if !lo.is_finite() || !hi.is_finite() {
            return None;
        }
        let (ax, ay, aw, ah) = area;
        let free = margin * aw.min(ah);
        let (w, h) = ((aw - 2.0 * free).max(1.0), (ah - 2.0 * free).max(1.0));
        let extent = hi - lo;
        // A point or a line seen end-on has no extent: any scale draws it.
        let sx = if extent.x > 0.0 {
            w / extent.x
        } else {
            f64::INFINITY
        };
        let sy = if extent.y > 0.0 {
            h / extent.y
        } else {
            f64::INFINITY
        };
        let scale = match sx.min(sy) {
            s if s.is_finite() && s > 0.0 => s,
            _ => 1.0,
        };
        let mid = (lo + hi) / 2.0;
        let center = right * mid.x + up * mid.y + forward * mid.z;
        Some(Camera {
            forward,
            right,
            up,
            center,
            scale,
            origin: (ax + aw / 2.0, ay + ah / 2.0),
            half: (extent.x * scale / 2.0, extent.y * scale / 2.0),
        })
    }

    /// The pixel rectangle the fitted points are drawn in: left, top, right, bottom.
    pub fn drawn(&self) -> (f64, f64, f64, f64) {
        let (x, y) = self.origin;
        let (hw, hh) = self.half;
        (x - hw, y - hh, x + hw, y + hh)
    }

    /// Where the press point `p` is drawn, and its depth in millimetres.
    pub fn project(&self, p: DVec3) -> ScreenPoint {
        let d = p - self.center;
        ScreenPoint {
            x: self.origin.0 + d.dot(self.right) * self.scale,
            y: self.origin.1 - d.dot(self.up) * self.scale,
            depth: d.dot(self.forward),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_view_has_a_right_handed_frame() {
        for (name, v) in View::ALL {
            let c = Camera::fit(
                v,
                [DVec3::ZERO, DVec3::ONE].into_iter(),
                (0.0, 0.0, 10.0, 10.0),
                0.0,
            )
            .expect("points");
            // right x up = towards the eye (-forward): what is drawn is not mirrored.
            assert!((c.right.cross(c.up) + c.forward).length() < 1e-12, "{name}");
            assert_eq!(View::from_name(name), Some(v));
        }
    }

    #[test]
    fn the_top_view_fits_the_box_with_its_margin_and_puts_y_up_the_page() {
        let pts = [
            DVec3::new(-100.0, -50.0, 0.0),
            DVec3::new(100.0, 50.0, 30.0),
        ];
        let c = Camera::fit(View::Top, pts.into_iter(), (0.0, 0.0, 220.0, 120.0), 0.05)
            .expect("points");
        // 6 px free all round: 208 x 108 for 200 x 100 mm, so 1.04 px/mm.
        assert!((c.scale - 1.04).abs() < 1e-12);
        let a = c.project(DVec3::new(-100.0, 50.0, 30.0));
        assert!(
            (a.x - 6.0).abs() < 1e-9 && (a.y - 8.0).abs() < 1e-9,
            "{a:?}"
        );
        let (l, t, r, b) = c.drawn();
        assert!((l - 6.0).abs() < 1e-9 && (t - 8.0).abs() < 1e-9);
        assert!((r - 214.0).abs() < 1e-9 && (b - 112.0).abs() < 1e-9);
        // Higher is nearer from above.
        assert!(c.project(DVec3::new(0.0, 0.0, 30.0)).depth < c.project(DVec3::ZERO).depth);
    }
}
