//! Join checks shared by `tests/blankholder.rs` and `tests/step_draw.rs`: eq. 4 computed
//! from the control points, independently of `die::continuity`, and G1 measured along
//! the shared boundary.

#![allow(dead_code)] // each test file uses its own subset

use dieface::geom::NurbsSurface;
use glam::DVec3;

/// Samples per boundary for the measured G1 figures (the 200).
pub const JOIN_SAMPLES: usize = 200;

/// The angle between two vectors in degrees.
pub fn angle_deg(a: DVec3, b: DVec3) -> f64 {
    a.cross(b).length().atan2(a.dot(b)).to_degrees()
}

/// Eq. 4 measured from the control points: `first` ends at its u = max boundary where
/// `second` starts. Returns (largest |S_j - S'_j|, largest angle between S_j - R_j and
/// T_j - S_j in degrees, spread max/min - 1 of |S_j - R_j| / |T_j - S_j| over the rows).
pub fn eq4(first: &NurbsSurface, second: &NurbsSurface) -> (f64, f64, f64) {
    let ((na, ma), (_, mb)) = (first.counts(), second.counts());
    assert_eq!(ma, mb, "the patches have different rows along the boundary");
    assert!(
        !first.is_rational() && !second.is_rational(),
        "eq. 4 on the control points is the C1 condition of polynomial patches"
    );
    let (mut gap, mut angle) = (0.0f64, 0.0f64);
    let (mut lo, mut hi) = (f64::INFINITY, 0.0f64);
    for j in 0..ma {
        let r = first.control_point(na - 2, j);
        let s = first.control_point(na - 1, j);
        let s2 = second.control_point(0, j);
        let t = second.control_point(1, j);
        gap = gap.max(s.distance(s2));
        let (before, after) = (s - r, t - s);
        assert!(
            before.length() > 0.0 && after.length() > 0.0,
            "a collapsed leg in row {j}"
        );
        angle = angle.max(angle_deg(before, after));
        let ratio = before.length() / after.length();
        lo = lo.min(ratio);
        hi = hi.max(ratio);
    }
    (gap, angle, hi / lo - 1.0)
}

/// G1 measured along the boundary at `JOIN_SAMPLES + 1` points: (largest gap, largest
/// angle between the normals in degrees).
pub fn measured_g1(first: &NurbsSurface, second: &NurbsSurface) -> (f64, f64) {
    let (ua, ub) = (first.domain_u().1, second.domain_u().0);
    let ((va0, va1), (vb0, vb1)) = (first.domain_v(), second.domain_v());
    let (mut gap, mut angle) = (0.0f64, 0.0f64);
    for i in 0..=JOIN_SAMPLES {
        let f = i as f64 / JOIN_SAMPLES as f64;
        let (va, vb) = (va0 + (va1 - va0) * f, vb0 + (vb1 - vb0) * f);
        gap = gap.max(first.point_at(ua, va).distance(second.point_at(ub, vb)));
        let (na, nb) = (
            first.normal(ua, va).expect("normal"),
            second.normal(ub, vb).expect("normal"),
        );
        angle = angle.max(angle_deg(na, nb));
    }
    (gap, angle)
}
