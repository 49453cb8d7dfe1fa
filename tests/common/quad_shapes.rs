//! Plane regions the quad-meshing tests and benchmark mesh (issue 18): simple shapes,
//! and regions like the paper's cases (paper 004, section 5: a door inner with many
//! inner loops).

#![allow(dead_code)]

use dieface::geom::mesh::quad::Region;
use glam::DVec2;

/// A circle of radius `r` round `c` as `n` points, counter-clockwise.
pub fn circle(c: DVec2, r: f64, n: usize) -> Vec<DVec2> {
    (0..n)
        .map(|k| {
            let t = std::f64::consts::TAU * k as f64 / n as f64;
            c + r * DVec2::new(t.cos(), t.sin())
        })
        .collect()
}

/// A rectangle `w` by `h` from `lo`, counter-clockwise.
pub fn rectangle(lo: DVec2, w: f64, h: f64) -> Vec<DVec2> {
    vec![
        lo,
        lo + DVec2::new(w, 0.0),
        lo + DVec2::new(w, h),
        lo + DVec2::new(0.0, h),
    ]
}

/// A rectangle `w` by `h` centred on `c` with corners rounded to `r`, `per_corner`
/// points on each corner arc.
pub fn rounded_rectangle(c: DVec2, w: f64, h: f64, r: f64, per_corner: usize) -> Vec<DVec2> {
    let (hx, hy) = (0.5 * w - r, 0.5 * h - r);
    let centres = [
        c + DVec2::new(hx, -hy),
        c + DVec2::new(hx, hy),
        c + DVec2::new(-hx, hy),
        c + DVec2::new(-hx, -hy),
    ];
    let mut out = Vec::new();
    for (k, centre) in centres.iter().enumerate() {
        let start = -std::f64::consts::FRAC_PI_2 + k as f64 * std::f64::consts::FRAC_PI_2;
        for s in 0..=per_corner {
            let t = start + std::f64::consts::FRAC_PI_2 * s as f64 / per_corner as f64;
            out.push(*centre + r * DVec2::new(t.cos(), t.sin()));
        }
    }
    out
}

/// A slot: a rounded rectangle whose ends are half circles.
pub fn slot(c: DVec2, length: f64, width: f64) -> Vec<DVec2> {
    rounded_rectangle(c, length, width, 0.5 * width, 8)
}

/// A 100 mm square.
pub fn square() -> Region {
    Region {
        outer: rectangle(DVec2::ZERO, 100.0, 100.0),
        holes: vec![],
    }
}

/// A disc of 50 mm radius.
pub fn disc() -> Region {
    Region {
        outer: circle(DVec2::ZERO, 50.0, 180),
        holes: vec![],
    }
}

/// An L: 120 mm legs, 50 mm wide.
pub fn ell() -> Region {
    Region {
        outer: vec![
            DVec2::new(0.0, 0.0),
            DVec2::new(120.0, 0.0),
            DVec2::new(120.0, 50.0),
            DVec2::new(50.0, 50.0),
            DVec2::new(50.0, 120.0),
            DVec2::new(0.0, 120.0),
        ],
        holes: vec![],
    }
}

/// A plate with one round hole off centre.
pub fn plate_with_hole() -> Region {
    Region {
        outer: rectangle(DVec2::ZERO, 200.0, 120.0),
        holes: vec![circle(DVec2::new(80.0, 60.0), 25.0, 90)],
    }
}

/// Like the paper's door inner (Fig. 13; 19 loops): a 900 by 700 mm panel with a
/// window opening, a cut corner and a notch, and 18 inner loops (the window, speaker
/// and lock openings, round and slotted holes).
pub fn door_inner() -> Region {
    let outer = vec![
        DVec2::new(0.0, 0.0),
        DVec2::new(820.0, 0.0),
        DVec2::new(900.0, 80.0),
        DVec2::new(900.0, 700.0),
        DVec2::new(520.0, 700.0),
        DVec2::new(520.0, 640.0),
        DVec2::new(380.0, 640.0),
        DVec2::new(380.0, 700.0),
        DVec2::new(0.0, 700.0),
    ];
    let mut holes = vec![
        rounded_rectangle(DVec2::new(450.0, 470.0), 560.0, 180.0, 40.0, 10),
        circle(DVec2::new(200.0, 200.0), 70.0, 72),
        rounded_rectangle(DVec2::new(760.0, 220.0), 90.0, 140.0, 20.0, 6),
        slot(DVec2::new(450.0, 120.0), 160.0, 30.0),
        slot(DVec2::new(450.0, 270.0), 120.0, 24.0),
    ];
    for k in 0..6 {
        holes.push(circle(DVec2::new(80.0 + 140.0 * k as f64, 40.0), 10.0, 24));
    }
    for k in 0..4 {
        holes.push(circle(DVec2::new(60.0, 330.0 + 90.0 * k as f64), 12.0, 24));
    }
    for k in 0..3 {
        holes.push(circle(DVec2::new(850.0, 400.0 + 90.0 * k as f64), 15.0, 24));
    }
    Region { outer, holes }
}
