//! Measuring a 2-D profile sketch (a step-draw section or a bead cross-section) by its
//! drawn segments, shared by `tests/addendum.rs` and `tests/beads.rs`.

#![allow(dead_code)] // each test file uses its own subset

use dieface::eval::sketch::Sketch;
use glam::DVec2;

/// `n + 1` points evenly spaced in the parameter of the sketch's curve.
pub fn samples(sk: &Sketch, n: usize) -> Vec<DVec2> {
    let (t0, t1) = sk.curve.domain();
    (0..=n)
        .map(|k| sk.curve.point_at(t0 + (t1 - t0) * k as f64 / n as f64))
        .collect()
}

/// The kinds of the drawn segments.
pub fn kinds(sk: &Sketch) -> Vec<&'static str> {
    sk.segments.iter().map(|g| g.kind).collect()
}

/// Start and end point of segment `k`.
pub fn ends(sk: &Sketch, k: usize) -> (DVec2, DVec2) {
    let (a, b) = sk.segments[k].range;
    (sk.curve.point_at(a), sk.curve.point_at(b))
}

/// The straight segments: (start, end) of each `line`.
pub fn lines(sk: &Sketch) -> Vec<(DVec2, DVec2)> {
    (0..sk.segments.len())
        .filter(|&k| sk.segments[k].kind == "line")
        .map(|k| ends(sk, k))
        .collect()
}

/// Lines that are not horizontal: a step draw's walls, a bead's flanks.
pub fn walls(sk: &Sketch) -> Vec<(DVec2, DVec2)> {
    lines(sk)
        .into_iter()
        .filter(|(a, b)| (b.y - a.y).abs() > 1e-9)
        .collect()
}

/// Horizontal lines: runs, flats, steps, flat tops.
pub fn flats(sk: &Sketch) -> Vec<(DVec2, DVec2)> {
    lines(sk)
        .into_iter()
        .filter(|(a, b)| (b.y - a.y).abs() <= 1e-9)
        .collect()
}

/// The angle of a wall from the vertical.
pub fn draft_of((a, b): (DVec2, DVec2)) -> f64 {
    (b.x - a.x).abs().atan2((b.y - a.y).abs())
}
